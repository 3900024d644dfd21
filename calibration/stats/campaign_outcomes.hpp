// How a resolved campaign's impacts ended (/dem/index: every impact that ended, whatever its
// status), and the share the bed captured: `ricochet stats` prints it for a campaign file
// (docs/commands/stats.md, "Outcomes"). A captured block is still in contact at the deck's t_max
// (`timeout`) or came to rest in the sand (`no_rebound`); the lab's blocks all rebounded, so the
// share is a result of the bed, with its exact interval.
#pragma once

#include <cstddef>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "impact/impact_set.hpp"
#include "stats/stats.hpp"

namespace ricochet::stats {

/// Where a captured impact's track ends: its last record (the deck's t_max for a timeout, the
/// rest for a no_rebound), which tells a block buried at rest from one still sliding on the
/// surface when t_max cut it short. SI units; NaN where the track lacks the column.
struct CapturedEnd {
  std::string id;
  std::string status;
  double t_s = std::numeric_limits<double>::quiet_NaN();
  double speed_mps = std::numeric_limits<double>::quiet_NaN();  ///< |(vx, vy)|
  double spin_radps = std::numeric_limits<double>::quiet_NaN();
  /// Depth of the block's lowest point below the levelled surface [m]; negative above it.
  double penetration_m = std::numeric_limits<double>::quiet_NaN();
  double ke_block_J = std::numeric_limits<double>::quiet_NaN();
};

struct CampaignOutcomes {
  std::string source;
  std::string where;                             ///< the filter applied, empty: none
  std::map<std::string, std::size_t> by_status;  ///< over the impacts kept
  std::size_t impacts = 0;                       ///< kept by the filter
  /// Those that ran to an outcome of the bed: every status but the refusals and numerical
  /// failures (invalid, lost_atoms, extraction_failed, crashed), which say nothing about it.
  std::size_t ran = 0;
  std::size_t captured = 0;  ///< timeout or no_rebound
  Proportion capture;        ///< captured / ran, 95 % Clopper-Pearson
  /// The captured impacts the file keeps a track of (/dem/tracks), in index order.
  std::vector<CapturedEnd> captured_ends;
};

/// Whether `status` is a numerical failure or a refusal (not an outcome of the bed).
bool is_numerical_failure(const std::string& status);
/// Whether `status` is a capture (timeout, no_rebound).
bool is_capture(const std::string& status);

/// The outcomes of the campaign file `path`'s index, over the impacts that match `where` (the
/// --where syntax, evaluated on each impact's id, shape and incident state as its spec records
/// them; the reflected velocities only where it rebounded, from `impacts`, the file's impact
/// set as already read and not filtered, so a condition on them keeps rebounds only). Returns
/// impacts = 0 for a file without /dem/index (a CSV, a lab set). Reads the last record of each
/// captured impact's track (captured_ends). Throws InputError (field `option`) for a malformed
/// filter, (file, /dem/tracks/ID) for a malformed track.
CampaignOutcomes campaign_outcomes(const std::string& path, const ImpactSet& impacts,
                                   const std::string& where = "",
                                   const std::string& option = "--where");

nlohmann::json to_json(const CampaignOutcomes& o);
/// Two lines or more: the counts by status, the captured share with its interval, then a line
/// per captured impact with a track: where it ends.
std::string format_text(const CampaignOutcomes& o);

}  // namespace ricochet::stats
