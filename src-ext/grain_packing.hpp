// The grain calibration's packing (grain_calibration.hpp, GrainCalibrationOptions::bed_cache):
// each design point's solid fraction, from the campaign file's records, the bed cache or the
// beds' grain counts, and its kriging over the grain parameters, which the solid-fraction band
// constrains the calibrated point with.
#pragma once

#include <map>
#include <openturns/OT.hxx>
#include <string>
#include <vector>

#include "campaign_store.hpp"
#include "grain_calibration.hpp"

namespace ricochet::dem {

/// Each design point's solid fraction [-] (GrainPoint::solid_fraction and its source): the mean
/// over the beds its replicas were hit on (one bed per point in a [design.sample] campaign), as
/// the campaign file records it (/dem/beds, record_bed_packing: it outlives the cache), else
/// measured once on the restart file in `cache` (when not empty; needs MPI initialised), else
/// (`from_grain_count`) estimated from the bed's grain count and the recorded beds of its
/// geometry (r.grain_count_estimates). `grain`: every impact's grain parameters
/// (campaign_grain_parameters); `index`: the file's /dem/index (read_campaign_index). Throws
/// InputError naming the file when a bed has none of these.
void measure_points_packing(GrainCalibrationResult& r, const std::string& campaign_h5,
                            const std::vector<CampaignEntry>& index, const std::string& cache,
                            bool from_grain_count,
                            const std::map<std::string, std::map<std::string, std::string>>& grain);

/// The solid fraction's kriging over the points' unit coordinates `u` (no nugget: a bed is
/// measured exactly); sets r.solid_fraction_q2 and each point's leave-one-out prediction.
OT::KrigingResult fit_packing(GrainCalibrationResult& r, const OT::Sample& u);

}  // namespace ricochet::dem
