// Checkpoints of a running impact, so that an impact killed with its session (a stiff bed's
// impact takes hours of a core) resumes where it was instead of starting again.
//
// Every `run.checkpoint_steps` steps the driver runs impact/checkpoint.in: LIGGGHTS writes its
// whole state as a restart file, WORK/checkpoint-new.restart; the driver renames it to
// WORK/checkpoint-N.restart and then commits WORK/checkpoint.json (this struct, with the deck's
// own state) by an atomic rename, which is what makes checkpoint N the current one; the older
// generation's restart is removed after. An impact started again in the
// same work folder with the same deck variables and decks (the fingerprint) reads the restart
// instead of its bed (setup.in, `resuming`), and ends bit for bit as the uninterrupted run:
// the chunk after a checkpoint sets its run up again, as the resumed run's first chunk does
// (tests/dem/cli_test.cpp, DemCheckpoint). A finished impact removes its checkpoints.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "params.hpp"

namespace ricochet::dem {

struct ImpactCheckpoint {
  std::string fingerprint;  ///< checkpoint_fingerprint() of the impact it belongs to
  long generation = 0;      ///< its files are WORK/checkpoint-<generation>.*
  long step0 = 0;           ///< the step at which the impact read its bed: the time origin
  long first_step = 0;      ///< the step after the block's insertion (steps are counted from it)
  long step = 0;            ///< the step the restart holds
  double t_s = 0;           ///< simulated time of the impact at that step [s]
  double cpu_s = 0;         ///< CPU seconds spent before it, over every segment and rank
  double wall_s = 0;        ///< wall seconds spent before it, over every segment
  double rayleigh_fraction = 0, hertz_fraction = 0;  ///< largest so far (fix check/timestep/gran)
  std::uintmax_t track_bytes = 0;                 ///< length of the deck's track file at that step
  std::vector<double> surface_before_m;           ///< surface profile before the impact (crater)
  std::vector<std::pair<long, double>> overlaps;  ///< (step, largest grain overlap / d) so far
  /// The deck's state variables (kDeckState) and their values at that step, as text.
  std::vector<std::pair<std::string, std::string>> deck_state;
};

/// The impact deck's string variables that a resumed run takes back as resume_NAME
/// (impact/setup.in): the counts of the insertion step and check.in's stop-criterion state.
inline const std::vector<std::string> kDeckState = {
    "n_atoms_start", "n_grains_start",  "n_grains_tolerated", "phase",  "impact_done",
    "status",        "t_contact_start", "t_contact_end",      "pen_max"};

/// A hash of the impact's deck variables (`name=value`, in order) and of the impact decks' text
/// (impact/*.in): a checkpoint is resumed only by the same impact on the same decks.
std::string checkpoint_fingerprint(const std::vector<std::pair<std::string, std::string>>& vars,
                                   const Decks& decks);

/// WORK/checkpoint-<generation> (the prefix of its .restart).
std::string checkpoint_prefix(const std::string& work_dir, long generation);
/// WORK/checkpoint-new: where impact/checkpoint.in writes before the driver renames.
std::string checkpoint_new_prefix(const std::string& work_dir);

/// The current checkpoint of WORK when it belongs to `fingerprint` and its files are all
/// there; nullopt otherwise (none, another impact's, or unreadable: the impact starts afresh).
std::optional<ImpactCheckpoint> read_checkpoint(const std::string& work_dir,
                                                const std::string& fingerprint);

/// Makes the files at checkpoint_new_prefix() generation c.generation and commits `c` as
/// WORK/checkpoint.json (atomic rename); then removes every other generation's files.
void commit_checkpoint(const std::string& work_dir, const ImpactCheckpoint& c);

/// Removes WORK's checkpoint files (the impact ended, or they belong to another impact).
void remove_checkpoints(const std::string& work_dir);

/// The deck variables that make setup.in resume from `c` (impact/setup.in, "Resuming").
std::vector<std::pair<std::string, std::string>> resume_variables(const ImpactCheckpoint& c,
                                                                  const std::string& work_dir);

/// JSON text of a checkpoint and back (for the ranks of an instance: rank 0 reads the file).
std::string checkpoint_to_json(const ImpactCheckpoint& c);
ImpactCheckpoint checkpoint_from_json(const std::string& text);

}  // namespace ricochet::dem
