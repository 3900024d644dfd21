// Internal machinery of the fit module: a bounded problem in normalised coordinates, NLopt
// BOBYQA local searches, multi-start, and the near-optimal interval walk. Exposed (in namespace
// detail) so that other calibrations in the project (e.g. uq's range calibration) reuse it.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "fit/fit.hpp"

namespace ricochet::fit::detail {

/// A minimisation problem over u in [0, 1]^dim (each variable scaled to its bound range).
class Problem {
 public:
  virtual ~Problem() = default;
  virtual std::size_t dim() const = 0;
  /// Objective at one point.
  virtual double eval(const std::vector<double>& u) = 0;
  /// Objective at points that follow from a search's design and settings alone, not from the
  /// data (row-major, dim per point): multi_start's design, and each local search's start and
  /// first interpolation points (BOBYQA's 2n + 1, Powell 2009). Fits that share a design
  /// evaluate the same such points, so a problem may share their results with the others
  /// (fit/collision_memo.hpp). Same values as eval_many().
  virtual std::vector<double> eval_starts(const std::vector<double>& points) {
    return eval_many(points);
  }
  /// Objective at many points (row-major, dim per point); override to batch the engine.
  virtual std::vector<double> eval_many(const std::vector<double>& points) {
    std::vector<double> out;
    const std::size_t d = dim();
    for (std::size_t i = 0; i * d < points.size(); ++i)
      out.push_back(
          eval(std::vector<double>(points.begin() + i * d, points.begin() + (i + 1) * d)));
    return out;
  }
  /// Runs independent searches; problems backed by a coroutine pool (fit/fibers.hpp) run them
  /// in lock-step so that their collisions share engine batches.
  virtual void parallel(std::vector<std::function<void()>>& tasks) {
    for (auto& t : tasks) t();
  }
  int evaluations = 0;  ///< collisions simulated so far (maintained by implementations)
};

struct LocalResult {
  std::vector<double> u;
  double f = std::numeric_limits<double>::infinity();
};

/// BOBYQA (NLopt LN_BOBYQA) over the variables with free[k] != 0, the others held at u0.
/// Stops at `stopval` (pass -inf for a full minimisation), after `max_evaluations`, or when a
/// step changes no variable by more than `xtol`. Returns the best point evaluated (NLopt's
/// round-off exits keep it too). The first `start_evaluations` evaluations go through
/// Problem::eval_starts.
LocalResult minimize_local(Problem& problem, const std::vector<double>& u0,
                           const std::vector<char>& free, double initial_step, double xtol,
                           int max_evaluations,
                           double stopval = -std::numeric_limits<double>::infinity(),
                           int start_evaluations = 0);

/// Multi-start: evaluates `design` (row-major unit points) in one batch, then runs BOBYQA from
/// its `starts` best points (as parallel tasks); the design and each run's start and first
/// interpolation points go through Problem::eval_starts. Returns the best end point (first in start
/// order among equals); fills the end point of every run and the design values.
LocalResult multi_start(Problem& problem, const std::vector<double>& design, int starts,
                        double xtol, int max_evaluations, std::vector<LocalResult>& ends,
                        std::vector<double>& design_values);

/// Polish (issue 35: a search on a coarse orientation rule, refined on a fine one): BOBYQA on
/// `problem` from the `count` best of `from` (by their f, on the coarse problem; duplicates
/// dropped), in parallel tasks, initial step 0.05 (a refinement, not a search). Returns the best
/// polished point; `ends` receives every polished end.
LocalResult polish(Problem& problem, std::vector<LocalResult> from, int count, double xtol,
                   int max_evaluations, std::vector<LocalResult>& ends);

/// Near-optimal interval of every variable j: {u_j : min over the other variables of f <=
/// threshold} (file comment of fit/fit.hpp). `inside_points` (row-major, in/out) holds verified
/// near-optimal points and must contain the optimum. Each side of each variable is one walk
/// (2 * dim parallel tasks): it starts from the known inside point furthest that way, steps
/// out (doubling while inside), then bisects to `resolution`; every verified point is appended
/// to `inside_points`. The interval of j is the hull of all those points along j (normalised
/// units), with the profile points (u_j, f) its walks visited.
struct UnitInterval {
  double lo = 0, hi = 0;
  bool lo_at_bound = false, hi_at_bound = false;
  std::vector<std::array<double, 2>> profile;  ///< (u_j, f)
};
std::vector<UnitInterval> near_optimal_intervals(Problem& problem, const LocalResult& best,
                                                 double threshold, double resolution,
                                                 std::vector<double>& inside_points, double xtol);

/// Classification and verdict text of an interval in physical units. `insensitive_at_upper`:
/// the rebound at the optimum does not change when the parameter goes to its upper bound, which
/// the verdict then says, in the words of the parameter's declared `role` (a friction or
/// rolling cap that is never reached).
void classify(ParameterInterval& interval, bool insensitive_at_upper,
              ParameterRole role = ParameterRole::kOther);

}  // namespace ricochet::fit::detail
