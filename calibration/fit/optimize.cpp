#include "fit/optimize.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlopt.hpp>
#include <numeric>
#include <stdexcept>

namespace ricochet::fit::detail {
namespace {

struct Wrap {
  Problem* problem;
  std::vector<double> u;           // full point; free coordinates overwritten per call
  std::vector<std::size_t> index;  // free coordinate -> full coordinate
  LocalResult best;
  int start_evaluations = 0;  // the first calls go through Problem::eval_starts
  int calls = 0;
};

double objective(unsigned n, const double* x, double* grad, void* data) {
  (void)grad;  // derivative-free
  auto* w = static_cast<Wrap*>(data);
  for (unsigned k = 0; k < n; ++k) w->u[w->index[k]] = std::clamp(x[k], 0.0, 1.0);
  const double f =
      w->calls++ < w->start_evaluations ? w->problem->eval_starts(w->u)[0] : w->problem->eval(w->u);
  // NaN would stall BOBYQA's model; treat an undefined rebound as a very bad fit.
  const double g = std::isfinite(f) ? f : 1e30;
  if (g < w->best.f) {
    w->best.f = g;
    w->best.u = w->u;
  }
  return g;
}

}  // namespace

LocalResult minimize_local(Problem& problem, const std::vector<double>& u0,
                           const std::vector<char>& free, double initial_step, double xtol,
                           int max_evaluations, double stopval, int start_evaluations) {
  Wrap w{&problem, u0, {}, {}, start_evaluations};
  for (std::size_t k = 0; k < u0.size(); ++k)
    if (free[k]) w.index.push_back(k);
  const unsigned n = static_cast<unsigned>(w.index.size());
  if (n == 0) {
    w.best.u = u0;
    w.best.f = problem.eval(u0);
    return w.best;
  }
  // BOBYQA needs at least two variables (its quadratic model uses 2n + 1 points); a single
  // free variable goes to NLopt's COBYLA, also a derivative-free Powell method.
  nlopt::opt opt(n >= 2 ? nlopt::LN_BOBYQA : nlopt::LN_COBYLA, n);
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_min_objective(objective, &w);
  opt.set_xtol_abs(xtol);
  opt.set_maxeval(max_evaluations);
  opt.set_stopval(stopval);
  std::vector<double> x(n), step(n);
  for (unsigned k = 0; k < n; ++k) {
    x[k] = std::clamp(u0[w.index[k]], 0.0, 1.0);
    // Keep the first trust region inside the box on the side with more room.
    step[k] = std::min(initial_step, std::max(x[k], 1.0 - x[k]));
  }
  opt.set_initial_step(step);
  double f = 0;
  try {
    opt.optimize(x, f);
  } catch (const nlopt::roundoff_limited&) {
    // Converged to round-off: the best point seen is the answer.
  } catch (const nlopt::forced_stop&) {
  }
  if (w.best.u.empty()) {  // no evaluation happened (cannot occur with maxeval >= 1)
    w.best.u = u0;
    w.best.f = problem.eval(u0);
  }
  return w.best;
}

LocalResult multi_start(Problem& problem, const std::vector<double>& design, int starts,
                        double xtol, int max_evaluations, std::vector<LocalResult>& ends,
                        std::vector<double>& design_values) {
  const std::size_t d = problem.dim();
  const std::size_t n = design.size() / d;
  design_values = problem.eval_starts(design);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  // Stable sort on (value, index): ties resolved by design order, so the starts are
  // deterministic.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const double fa = std::isfinite(design_values[a]) ? design_values[a] : 1e300;
    const double fb = std::isfinite(design_values[b]) ? design_values[b] : 1e300;
    return fa < fb;
  });
  const std::vector<char> all(d, 1);
  const std::size_t runs = std::min<std::size_t>(static_cast<std::size_t>(std::max(starts, 1)), n);
  // The initial trust region spans about one design cell: the start is the best point of its
  // neighbourhood, so a larger first step would only leave it.
  const double step = std::clamp(0.5 / std::pow(static_cast<double>(n), 1.0 / d), 0.02, 0.2);
  ends.assign(runs, LocalResult{});
  std::vector<std::function<void()>> tasks;
  for (std::size_t r = 0; r < runs; ++r) {
    tasks.push_back([&, r] {
      const std::size_t i = order[r];
      const std::vector<double> u0(design.begin() + i * d, design.begin() + (i + 1) * d);
      // BOBYQA's start and its 2d first interpolation points (COBYLA's d + 1, d = 1, are
      // among them).
      ends[r] =
          minimize_local(problem, u0, all, step, xtol, max_evaluations,
                         -std::numeric_limits<double>::infinity(), 2 * static_cast<int>(d) + 1);
    });
  }
  problem.parallel(tasks);
  LocalResult best;
  for (auto& e : ends)
    if (e.f < best.f) best = e;
  // The best design point is an answer too: BOBYQA moves a start that lies closer than its
  // initial step to a bound (Powell 2009) and may never evaluate it, and the result must never
  // be worse than a start already evaluated (a warm start: a calibrated model's own values).
  if (n > 0 && std::isfinite(design_values[order[0]]) && design_values[order[0]] < best.f) {
    best.u.assign(design.begin() + order[0] * d, design.begin() + (order[0] + 1) * d);
    best.f = design_values[order[0]];
  }
  return best;
}

LocalResult polish(Problem& problem, std::vector<LocalResult> from, int count, double xtol,
                   int max_evaluations, std::vector<LocalResult>& ends) {
  std::stable_sort(from.begin(), from.end(),
                   [](const LocalResult& a, const LocalResult& b) { return a.f < b.f; });
  std::vector<LocalResult> starts;
  for (auto& r : from) {
    if (static_cast<int>(starts.size()) >= count) break;
    if (r.u.empty() ||
        std::any_of(starts.begin(), starts.end(), [&](const LocalResult& s) { return s.u == r.u; }))
      continue;
    starts.push_back(std::move(r));
  }
  const std::vector<char> all(problem.dim(), 1);
  ends.assign(starts.size(), LocalResult{});
  std::vector<std::function<void()>> tasks;
  for (std::size_t r = 0; r < starts.size(); ++r)
    tasks.push_back([&, r] {
      ends[r] = minimize_local(problem, starts[r].u, all, 0.05, xtol, max_evaluations);
    });
  problem.parallel(tasks);
  LocalResult best;
  for (const auto& e : ends)
    if (e.f < best.f) best = e;
  return best;
}

std::vector<UnitInterval> near_optimal_intervals(Problem& problem, const LocalResult& best,
                                                 double threshold, double resolution,
                                                 std::vector<double>& inside_points, double xtol) {
  const std::size_t d = problem.dim();
  const int inner_evaluations = 30 + 5 * static_cast<int>(d);
  const double first_step = std::max(2.0 * resolution, 0.01);
  std::vector<std::vector<std::array<double, 2>>> profiles(2 * d);

  // One side of one variable.
  auto walk = [&](std::size_t j, int dir) {
    auto& profile = profiles[2 * j + (dir > 0 ? 1 : 0)];
    std::vector<char> others(d, 1);
    others[j] = 0;
    // Is u_j = v near-optimal? Tries the warm start first (often already inside), then
    // re-optimises the other variables from it, stopping as soon as the threshold is met.
    // Path following along the profile: the other variables at u_j = v are predicted by
    // extrapolating the last two verified points (secant); `prev` is empty before there are two.
    std::vector<double> prev;
    auto inside = [&](double v, const std::vector<double>& warm, std::vector<double>& found) {
      std::vector<double> u = warm;
      u[j] = v;
      double f = INFINITY;
      if (!prev.empty() && prev[j] != warm[j]) {
        const double s = (v - warm[j]) / (warm[j] - prev[j]);
        for (std::size_t k = 0; k < d; ++k)
          if (k != j) u[k] = std::clamp(warm[k] + s * (warm[k] - prev[k]), 0.0, 1.0);
        f = problem.eval(u);
        if (f > threshold) {
          u = warm;
          u[j] = v;
          f = INFINITY;
        }
      }
      // Then the warm start itself (often already inside), then a re-optimisation of the
      // other variables from it, stopping as soon as the threshold is met.
      if (f > threshold) f = problem.eval(u);
      if (f > threshold && d > 1) {
        const LocalResult r =
            minimize_local(problem, u, others, 0.05, xtol, inner_evaluations, threshold);
        if (r.f < f) {
          f = r.f;
          u = r.u;
        }
      }
      profile.push_back({v, f});
      found = u;
      const bool ok = f <= threshold;
      if (ok) inside_points.insert(inside_points.end(), u.begin(), u.end());
      return ok;
    };
    const double bound = dir < 0 ? 0.0 : 1.0;
    // Start from the verified near-optimal point furthest along this direction (good design
    // points and other starts often got there already).
    std::size_t from = 0;
    for (std::size_t i = 0; (i + 1) * d <= inside_points.size(); ++i)
      if (dir * inside_points[i * d + j] > dir * inside_points[from * d + j]) from = i;
    std::vector<double> warm(inside_points.begin() + from * d,
                             inside_points.begin() + (from + 1) * d);
    std::vector<double> found;
    double last_in = warm[j];
    bool reached = last_in == bound;
    double first_out = NAN;
    double step = first_step;
    while (!reached) {
      const double v = std::clamp(last_in + dir * step, 0.0, 1.0);
      if (inside(v, warm, found)) {
        last_in = v;
        prev = warm;
        warm = found;
        reached = v == bound;
        step *= 2.0;
      } else {
        first_out = v;
        break;
      }
    }
    if (!reached) {
      // Bisection between the last verified inside value and the first outside one.
      while (std::fabs(first_out - last_in) > resolution) {
        const double mid = 0.5 * (first_out + last_in);
        if (inside(mid, warm, found)) {
          last_in = mid;
          prev = warm;
          warm = found;
        } else {
          first_out = mid;
        }
      }
    }
  };
  std::vector<std::function<void()>> tasks;
  for (std::size_t j = 0; j < d; ++j)
    for (int dir : {-1, +1}) tasks.push_back([&, j, dir] { walk(j, dir); });
  problem.parallel(tasks);

  // The hull of every verified near-optimal point: the near-optimal set need not be connected.
  std::vector<UnitInterval> out(d);
  for (std::size_t j = 0; j < d; ++j) {
    UnitInterval& iv = out[j];
    iv.lo = iv.hi = best.u[j];
    for (std::size_t i = 0; (i + 1) * d <= inside_points.size(); ++i) {
      iv.lo = std::min(iv.lo, inside_points[i * d + j]);
      iv.hi = std::max(iv.hi, inside_points[i * d + j]);
    }
    iv.lo_at_bound = iv.lo <= 0.0;
    iv.hi_at_bound = iv.hi >= 1.0;
    iv.profile.push_back({best.u[j], best.f});
    for (int s = 0; s < 2; ++s)
      iv.profile.insert(iv.profile.end(), profiles[2 * j + s].begin(), profiles[2 * j + s].end());
    std::sort(iv.profile.begin(), iv.profile.end());
  }
  return out;
}

namespace {

std::string num(double v) {
  return fmt::format("{:.3g}", v);
}

// Why a parameter stops mattering: a cap that is never reached, or no dependence at all.
std::string cap_reason(const std::string& name, ParameterRole role) {
  if (role == ParameterRole::kFrictionCap)
    return "the contact sticks: the friction cap " + name + "*fn is never reached";
  if (role == ParameterRole::kRollingCap)
    return "the rolling moment never reaches its cap " + name + "*l*fn";
  return "the rebound does not depend on " + name + " there";
}

}  // namespace

void classify(ParameterInterval& iv, bool insensitive_at_upper, ParameterRole role) {
  const std::string unit = iv.unit.empty() || iv.unit == "-" ? "" : " " + iv.unit;
  if (!iv.lo_at_bound && !iv.hi_at_bound) {
    iv.status = Identifiability::kIdentified;
    iv.statement = iv.name + " in [" + num(iv.lo) + ", " + num(iv.hi) + "]" + unit;
  } else if (!iv.lo_at_bound) {
    iv.status = Identifiability::kLowerBoundOnly;
    iv.statement = iv.name + " >= " + num(iv.lo) + unit +
                   ", upper bound not identified (fits within the noise threshold up to the "
                   "bound " +
                   num(iv.bound_hi) + ")";
    if (insensitive_at_upper) iv.statement += ": " + cap_reason(iv.name, role);
  } else if (!iv.hi_at_bound) {
    iv.status = Identifiability::kUpperBoundOnly;
    iv.statement = iv.name + " <= " + num(iv.hi) + unit +
                   ", lower bound not identified (fits within the noise threshold down to the "
                   "bound " +
                   num(iv.bound_lo) + ")";
  } else {
    iv.status = Identifiability::kNotIdentified;
    // The near-optimal set reaches both bounds; it need not be connected, so do not claim
    // that every value in between fits.
    iv.statement = iv.name + " not identified: near-optimal values reach both bounds " +
                   num(iv.bound_lo) + " and " + num(iv.bound_hi) + unit;
  }
}

}  // namespace ricochet::fit::detail
