// A sphere-drop study (`ricochet dem drop`; docs/commands/dem.md, docs/granular-impact-checks.md):
// a sphere dropped into a bed from several heights, on one bed per replica seed, the grains'
// angle of repose (mu = tan theta_r, the friction of Uehara et al. 2003's law), and the drops
// gathered for the analysis (drop_analysis.hpp). The results file and its resume are
// drop_store.hpp; one drop and one repose run are drop.hpp.
#pragma once

#include <mpi.h>

#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "drop.hpp"
#include "drop_analysis.hpp"
#include "drop_store.hpp"
#include "params.hpp"

namespace ricochet::dem {

/// Which drops a study runs, where, and how it analyses them.
struct DropStudyOptions {
  std::vector<double> heights_m = {0.05, 0.1, 0.2, 0.5, 1.0};  ///< h of each drop [m]
  std::vector<long> seeds;  ///< replica seeds (a bed each); empty: the decks' own seeds, one bed
  std::string cache_dir = "dem-cache";  ///< bed cache (ensure_bed)
  std::string work_dir = "dem-work";    ///< per-drop folders and the repose run's
  double mu = 0;                        ///< > 0: mu = tan(angle of repose) imposed, no repose run
  DropStudyAnalysisOptions analysis;
};

/// The overrides of every drop of a study, by section of `--set SECTION.NAME=VALUE`.
struct DropStudySets {
  DropSpec base;                              ///< bed, block and drop overrides
  std::map<std::string, std::string> repose;  ///< repose/in.repose's own parameters
};

/// Parses `--set` assignments in order: bed.* and block.* are checked by apply_set_option as for
/// every dem command; drop.* and repose.* against drop_deck_params and repose_deck_params, as
/// positive numbers (y_drop_m and h_start_m may be 0). Throws InputError(file "<command line>",
/// field) on a malformed assignment, an unknown section or name, or a bad value.
DropStudySets parse_drop_sets(const Decks& decks, const std::vector<std::string>& sets);

/// A repose run as stored in FILE.repose.json: status, message, angle_deg, angle_se_deg, slope,
/// slope_se, mu = tan(angle), fitted_bins, fitted_x_m, grains, wall_s, work_dir, and the heap's
/// surface profile (profile_x_m, profile_h_m).
nlohmann::json repose_to_json(const ReposeResult& r);

/// The friction of a study's Uehara law.
struct StudyFriction {
  double mu = 0;
  bool imposed = false;   ///< DropStudyOptions::mu, no repose run
  nlohmann::json repose;  ///< repose_to_json of the run (null when imposed)
};

/// mu imposed (options.mu > 0), or from the repose run: read back from `repose_path` when the
/// file exists (a resumed study), else run_repose with the study's bed overrides (the decks'
/// seeds) in work_dir/repose (collective on comm) and written to `repose_path` by rank 0 (when not
/// empty), a failed run too. Throws std::runtime_error when the run gives no slope.
StudyFriction study_friction(const Decks& decks, const DropStudySets& sets,
                             const DropStudyOptions& options, const std::string& repose_path,
                             MPI_Comm comm);

/// The drops a study ran now, with their replica seed (-1: the decks' own seeds), and the bed of
/// the last one.
struct DropStudyRun {
  std::vector<std::pair<DropResult, long>> fresh;
  BedFiles bed;
};

/// Runs the study's drops on comm (collective): for each seed (none: the decks' own seeds) and
/// each height, the drop `hH` (`hH-sSEED` with a seed) on its bed (ensure_bed), skipping the
/// ids in `done` (a resumed study: store->done_ids(), read before the repose run so that a
/// damaged file stops the study first). On rank 0, `on_drop` sees each result, which is then
/// appended to `store` (when not null).
DropStudyRun run_drop_study(const Decks& decks, const DropStudySets& sets,
                            const DropStudyOptions& options, const std::set<std::string>& done,
                            const DropStore* store, MPI_Comm comm,
                            const std::function<void(const DropResult&)>& on_drop = {});

/// Every drop of the study, in file order: the stored ones (with this run's) when there is a
/// file, else this run's.
std::vector<StudyDrop> study_drops(const DropStore* store, const DropStudyRun& run);

/// The friction's keys of the `ricochet dem drop --json` document: mu, mu_source ("--mu" or
/// "repose run") and, with a repose run, repose (its JSON without the profile).
nlohmann::json to_json(const StudyFriction& friction);

}  // namespace ricochet::dem
