// Where a grain-parameter design rebounds at all (the grain calibration's rebound region,
// grain_calibration.hpp; amendment of 2026-12-05 to the sand recalibration's plan,
// docs/resolved-model.md, "Recalibration with what sand has").
//
// Why: the V_out surrogate is fitted to the rebounds only, so it knows nothing of the design
// points whose block never left the bed (a timeout, no_rebound, or the end wall of the longest
// bed run), and its optimum may lie among them, where the bed gives no rebound to compare with
// the lab's (every lab release rebounded). The region is where the rebound is the likelier
// outcome.
//
// Model: indicator kriging (Journel 1983, Math. Geol. 15:445-468): each design point's rebound
// fraction (per impact 1 for a rebound, 0 for none; its impacts' mean) is kriged over the
// grain parameters in the V_out surrogate's unit coordinates (grain_surrogate.hpp, no nugget),
// and its kriging mean is read as the probability of a rebound; the calibrated point is searched
// only where it is at least GrainCalibrationOptions::rebound_threshold. Its default, 0.9, is the
// one-sided 95 % lower bound of the lab's own rebound rate: every one of the 28 lab cylinder
// releases rebounded, and 0.9^28 = 0.05 (Clopper and Pearson 1934, Biometrika 26:404).
#pragma once

#include <map>
#include <openturns/OT.hxx>
#include <optional>
#include <string>
#include <vector>

#include "campaign_store.hpp"
#include "grain_calibration.hpp"

namespace ricochet::dem {

/// Every design point's outcomes, rebounds or not, into r.rebound_points (points grouped by their
/// values of r.parameters, as the V_out surrogate groups its replicas). Counted per impact: a
/// rebound (1), a timeout or no_rebound (0), an end wall (0) unless a rerun on a longer bed
/// supersedes it (an impact of the index whose id is its id followed by "-Lx", campaign.hpp
/// end_wall_reruns: the rerun counts instead); other statuses (crashed) are not counted. Every
/// impact of the index is tallied, whatever GrainCalibrationOptions::where keeps of the rebounds.
/// `grain`: every impact's grain parameters (campaign_grain_parameters).
void tally_rebounds(GrainCalibrationResult& r, const std::vector<CampaignEntry>& index,
                    const std::map<std::string, std::map<std::string, std::string>>& grain);

/// The indicator kriging of r.rebound_points over the unit coordinates of r.lower, r.upper (the
/// rebound points' box; a point outside it has coordinates outside [0, 1]), and its
/// leave-one-out agreement (r.rebound_loo_agreement: the share of points whose prediction by the
/// others is on their observed side of 0.5, the likelier outcome). Empty when every counted
/// impact rebounded: there is nothing to avoid.
std::optional<OT::KrigingResult> fit_rebound_region(GrainCalibrationResult& r);

}  // namespace ricochet::dem
