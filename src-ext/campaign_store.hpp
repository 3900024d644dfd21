// The campaign file (HDF5, docs/commands/dem.md "Campaign file"): the index of finished impacts,
// their tracks, and /impacts in the impact-set schema rewritten from the index. Every write holds
// an flock on PATH.lock, so that several processes can append to one file.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "bed.hpp"
#include "impact_run.hpp"
#include "params.hpp"

namespace ricochet::dem {

/// One row of the campaign index (every impact that ended, whatever its status).
struct CampaignEntry {
  std::string id, status, message, shape, bed_key, work_dir;
  std::string params;  ///< JSON: the spec (spec_json) plus "effective" bed and block parameters
  std::vector<double> values;  ///< aligned with campaign_value_names()
};
/// Numeric columns of /dem/index/values.
const std::vector<std::string>& campaign_value_names();

/// Appends one finished impact to the campaign file `path` (under an flock on PATH.lock): its
/// track, its index row, its picture (/dem/snapshot) when it has one, then rewrites /impacts (the
/// impact-set schema) from the index.
/// `params_json` records the spec. Used by run_campaign and by `ricochet dem impact --out`.
void append_result(const std::string& path, const ImpactResult& result, const ImpactSpec& spec,
                   const std::string& design_name);

/// Records the packing of bed `key` (bed.hpp, measure_packing) in the campaign file as
/// /dem/beds/KEY with attributes grains, grain_volume_m3, bed_volume_m3, solid_fraction and
/// bulk_density_kg_m3 (under the file's exclusive lock; a record of the same key is rewritten).
/// Why: the file outlives the bed cache (a machine that is not kept loses the beds, about 26 MB
/// each), and calibrate-grains' solid-fraction band needs every design point's packing.
void record_bed_packing(const std::string& path, const std::string& key, const BedPacking& packing);
/// The packings the campaign file records, by bed key (empty without a file or a record).
std::map<std::string, BedPacking> read_bed_packings(const std::string& path);

/// Reads the index of a campaign file (empty when the file or the index does not exist).
std::vector<CampaignEntry> read_campaign_index(const std::string& path);

/// Reads the track of impact `id` (/dem/tracks/ID) under the file's shared lock, with the
/// library's reader (impact/block_track.hpp: by the names of its `columns` attribute, so that
/// files written before a column existed read with that column NaN). Throws std::runtime_error
/// when the file does not exist, InputError when it has no such track or a malformed one.
BlockTrack read_campaign_track(const std::string& path, const std::string& id);

/// JSON record of a spec (shape, vin, alpha, seed, overrides).
std::string spec_json(const ImpactSpec& spec);
/// spec_json plus the impact's effective grain-scale parameters ("effective": {"bed", "block"}).
std::string params_json(const ImpactSpec& spec, const ImpactResult& result);

/// Rewrites /impacts (the impact-set schema) from the index entries whose status is "rebound".
void rewrite_impact_set(const std::string& path, const std::vector<CampaignEntry>& entries,
                        const std::string& design_name);

/// Removes impacts `ids` from the campaign file (their index rows and tracks; /impacts is
/// rewritten) under its exclusive lock, so that the next run of the design runs them again: the
/// repair of a record that a fault of the program wrote (`dem campaign --forget`). Returns the
/// entries removed, in the file's order; an id the file does not have is an InputError(path, 0,
/// "--forget") listing the file's ids. Nothing is removed unless every id is found.
std::vector<CampaignEntry> forget_impacts(const std::string& path,
                                          const std::vector<std::string>& ids);

/// Records that impact `id` is running (group /dem/running/ID with its work folder), so that a
/// killed run can tell it apart on resume.
void mark_running(const std::string& path, const std::string& id, const std::string& work_dir);

}  // namespace ricochet::dem
