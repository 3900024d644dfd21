// Which pending impact of a campaign runs next, and on which LIGGGHTS instance (campaign.cpp,
// run_pending). With one instance the design's order. With several, each instance (a "group" of
// ranks_per_impact ranks) takes the next impact as soon as it is free, so that no instance waits
// for another: impacts differ in cost by up to 8x (a rebound in 20 min, a timeout in 70 min at
// 1.5e9 Pa), and the earlier schedule, waves of beds dealt round robin with a barrier after each
// wave, left one core idle for up to an impact's length at each wave's end and for a whole bed's
// build when a wave had fewer beds to build than instances.
#pragma once

#include <string>
#include <vector>

namespace ricochet::dem {

/// The order in which the pending impacts run, as positions into `bed_keys` (each pending
/// impact's bed key, in design order). One group: the design's order, each bed built when its
/// first impact comes (a design ordered cheap to expensive keeps what its order put first). Several
/// groups: the impacts of beds the cache holds (`cached`, aligned with bed_keys) first, then bed
/// by bed in the order of each bed's first pending impact, a bed's impacts together and in design
/// order, so that a bed's impacts follow its build and a session stopped early keeps impacts
/// rather than beds.
std::vector<int> schedule_order(const std::vector<std::string>& bed_keys,
                                const std::vector<char>& cached, int groups);

/// Claims the next impact for one group; its rank 0 calls it, under an flock on
/// `claims_path`.lock (file_lock.hpp). `claims_path` lists the positions claimed so far in this
/// run, one per line (run_pending empties it before the first claim). The claim is the first
/// unclaimed position of `order` whose bed `cache_dir` holds; else the first whose bed nobody
/// builds (no other claim has that bed, and bed_building says no process holds its lock): this
/// group builds it; else the first (another group builds its bed: this one waits for it in
/// ensure_bed). Returns -1 when every position is claimed. `waits`, when given, is set to whether
/// the claim is of that last kind (for the log line that says so). Throws std::runtime_error
/// naming the file when it cannot be locked or written.
int claim_next(const std::string& claims_path, const std::vector<int>& order,
               const std::vector<std::string>& bed_keys, const std::string& cache_dir,
               bool* waits = nullptr);

}  // namespace ricochet::dem
