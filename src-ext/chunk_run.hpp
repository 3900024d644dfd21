// A deck run in chunks with the driver's checks between them: the loop shared by the impact
// (impact_run.cpp) and the sphere drop (drop.cpp). After every `chunk_steps` steps: the atoms
// (`atoms_lost`: a message when too many left the box, status lost_atoms), the body's state
// (NaN), the time step against kTimestepLimit x the Rayleigh and Hertz times of
// `fix check/timestep/gran` (fix id ts_check), then the deck's own stop criterion file, which sets
// the string variables `done_variable` ("1" when finished) and `status`.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "liggghts.hpp"

namespace ricochet::dem {

/// Largest time step, as a fraction of the Rayleigh and Hertz times, that a run accepts.
inline constexpr double kTimestepLimit = 0.2;

struct ChunkOutcome {
  std::string status, message;
  double rayleigh_fraction = 0, hertz_fraction = 0;  ///< largest seen
  /// True when the deck's criterion ended the run (its summary may then be evaluated); false
  /// for the driver's own failures (lost_atoms, nan, timestep), after which the body's state may
  /// be gone or meaningless.
  bool deck_stopped = false;
};

struct ChunkRun {
  long chunk_steps = 100;
  std::string check_file;     ///< the deck's stop criterion (run after each chunk)
  std::string done_variable;  ///< string variable set to "1" by check_file when finished
  std::string body;           ///< "block", "sphere": named in the NaN message
  std::vector<std::string> state_variables;  ///< equal-style variables that must stay finite
  /// Called when the atom count differs from the start's: a message ends the run as lost_atoms,
  /// an empty string lets it go on (e.g. a few grains splashed out of the box).
  std::function<std::string(double t_s)> atoms_lost;
  long expected_atoms = 0;
  std::function<void(double t_s)> progress;  ///< optional
  /// Optional checkpoints (impact_checkpoint.hpp): called after the deck's criterion whenever
  /// (step - checkpoint_from_step) is a multiple of checkpoint_every_steps and the run goes on,
  /// with the outcome so far; the chunk after one sets its run up again (neighbour lists built
  /// anew), as a run resumed from it does, so that both continue bit for bit the same.
  long checkpoint_every_steps = 0;
  long checkpoint_from_step = 0;
  std::function<void(const ChunkOutcome& so_far)> checkpoint;
};

/// Runs chunks until the deck or a check ends the run. Collective on the instance's ranks.
ChunkOutcome run_chunks(Liggghts& lmp, const ChunkRun& run);

}  // namespace ricochet::dem
