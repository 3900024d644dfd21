#include "chunk_run.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>

namespace ricochet::dem {

ChunkOutcome run_chunks(Liggghts& lmp, const ChunkRun& run) {
  ChunkOutcome o;
  // Between chunks only variables are evaluated (check.in), nothing LIGGGHTS sets up changes:
  // "pre no" skips the set-up of every later run, which otherwise rebuilt the neighbour lists
  // at each chunk (45 of an impact's 111 rebuilds, issue 13's profile). "post no": no timing
  // breakdown per chunk in the log.
  for (bool setup = true;;) {
    lmp.command(setup ? fmt::format("run {} post no", run.chunk_steps)
                      : fmt::format("run {} pre no post no", run.chunk_steps));
    setup = false;
    const double t = lmp.time_s();
    if (lmp.natoms() != run.expected_atoms) {
      std::string lost = run.atoms_lost ? run.atoms_lost(t)
                                        : fmt::format("{} atoms at t = {:.4f} s, expected {}",
                                                      lmp.natoms(), t, run.expected_atoms);
      if (!lost.empty()) {
        o.status = "lost_atoms";
        o.message = std::move(lost);
        return o;
      }
    }
    bool finite = true;
    for (const auto& v : run.state_variables)
      finite =
          finite && std::isfinite(lmp.number(v).value_or(std::numeric_limits<double>::quiet_NaN()));
    if (!finite) {
      o.status = "nan";
      o.message = fmt::format("the {} state is not finite at t = {:.4f} s", run.body, t);
      return o;
    }
    o.rayleigh_fraction = std::max(o.rayleigh_fraction, lmp.fix_vector("ts_check", 0));
    o.hertz_fraction = std::max(o.hertz_fraction, lmp.fix_vector("ts_check", 1));
    if (o.rayleigh_fraction > kTimestepLimit || o.hertz_fraction > kTimestepLimit) {
      o.status = "timestep";
      o.message = fmt::format(
          "time step {:.3g} s is {:.2f} of the Rayleigh time and {:.2f} of the Hertz time "
          "(limit {}): lower dt_frac",
          lmp.timestep_s(), o.rayleigh_fraction, o.hertz_fraction, kTimestepLimit);
      return o;
    }
    lmp.file(run.check_file);
    if (run.progress) run.progress(t);
    if (lmp.string(run.done_variable).value_or("1") == "1") {
      o.status = lmp.string("status").value_or("unknown");
      o.deck_stopped = true;
      return o;
    }
    if (run.checkpoint && run.checkpoint_every_steps > 0 &&
        (lmp.step() - run.checkpoint_from_step) % run.checkpoint_every_steps == 0) {
      run.checkpoint(o);
      setup = true;
    }
  }
}

}  // namespace ricochet::dem
