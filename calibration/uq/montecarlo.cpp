#include "uq/montecarlo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlopt.hpp>
#include <stdexcept>

#include "common/clock.hpp"
#include "common/progress.hpp"
#include "fit/design.hpp"
#include "stats/stats.hpp"

namespace ricochet::uq {

std::vector<double> MonteCarloResult::component(int k) const {
  std::vector<double> out;
  out.reserve(vout.size());
  for (std::size_t i = 0; i < vout.size(); ++i)
    if (status[i] == static_cast<int>(CollisionStatus::kOk)) out.push_back(vout[i][k]);
  return out;
}

RandomDraws draw(std::size_t runs, std::size_t varied, std::size_t incident_pool,
                 std::uint64_t seed) {
  // One stream, one row per run: the varied parameters' uniforms, then the incident pick and
  // the orientation. A run's numbers do not depend on the chunking or the thread count.
  const std::size_t d = varied + 2;
  const std::vector<double> u = fit::uniform_unit_sample(d, runs, seed);
  RandomDraws r;
  r.u_params.resize(runs * varied);
  r.incident.resize(runs);
  r.u_alpha.resize(runs);
  for (std::size_t i = 0; i < runs; ++i) {
    for (std::size_t k = 0; k < varied; ++k) r.u_params[i * varied + k] = u[i * d + k];
    const double pick =
        u[i * d + varied] * static_cast<double>(std::max<std::size_t>(incident_pool, 1));
    r.incident[i] = std::min<std::size_t>(static_cast<std::size_t>(pick),
                                          std::max<std::size_t>(incident_pool, 1) - 1);
    r.u_alpha[i] = u[i * d + varied + 1];
  }
  return r;
}

void check_inputs(const Model& model, const std::vector<ParameterInput>& inputs) {
  for (std::size_t a = 0; a < inputs.size(); ++a) {
    const ParameterInput& in = inputs[a];
    const std::size_t i = model.index(in.name);  // throws listing the names
    const ParameterSpec& s = model.spec(i);
    if (in.distribution.lower() < s.lower - 1e-12 || in.distribution.upper() > s.upper + 1e-12)
      throw std::invalid_argument("distribution of " + in.name + " (" +
                                  in.distribution.description() + ") leaves the bounds [" +
                                  std::to_string(s.lower) + ", " + std::to_string(s.upper) + "]");
    for (std::size_t b = 0; b < a; ++b)
      if (inputs[b].name == in.name)
        throw std::invalid_argument("parameter " + in.name + " is varied twice");
  }
}

namespace {

// Engine work shared by both entry points. `quantile(k, u)` maps the k-th uniform of a run to the
// parameter value.
template <class Quantile>
MonteCarloResult simulate_runs(const Model& model, const Shape& shape,
                               const std::vector<ParameterInput>& inputs,
                               const MonteCarloOptions& o, const RandomDraws& r,
                               Quantile&& quantile, const ChunkCallback& on_chunk,
                               std::size_t first_run) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t N = r.incident.size(), V = inputs.size(), P = model.parameter_count();
  std::vector<std::size_t> index;
  for (const auto& in : inputs) index.push_back(model.index(in.name));
  MonteCarloResult res;
  for (const auto& in : inputs) res.varied.push_back(in.name);
  res.inputs.assign(N * V, 0.0);
  res.vin.assign(N, Vel3{});
  res.alpha_rad.assign(N, 0.0);
  res.vout.assign(N, Vel3{});
  res.status.assign(N, 0);
  const std::size_t chunk = std::max<std::size_t>(1, o.chunk);
  Progress bar("montecarlo", N - std::min(first_run, N), o.progress);
  std::vector<CollisionCase> cases;
  std::vector<double> params;
  for (std::size_t begin = first_run; begin < N; begin += chunk) {
    const std::size_t end = std::min(N, begin + chunk);
    cases.resize(end - begin);
    params.assign((end - begin) * P, 0.0);
    for (std::size_t i = begin; i < end; ++i) {
      double* row = params.data() + (i - begin) * P;
      std::copy(model.values().begin(), model.values().end(), row);
      for (std::size_t k = 0; k < V; ++k) {
        const double x = quantile(k, r.u_params[i * V + k]);
        res.inputs[i * V + k] = x;
        row[index[k]] = x;
      }
      CollisionCase& c = cases[i - begin];
      double alpha = o.alpha_min_rad + (o.alpha_max_rad - o.alpha_min_rad) * r.u_alpha[i];
      if (o.incident) {
        const Impact& im = o.incident->impacts[r.incident[i]];
        c.vin = im.vin;
        if (im.alpha_in) alpha = *im.alpha_in;
      } else {
        c.vin = o.vin;
      }
      c.alpha_rad = shape.is_disc() ? 0.0 : alpha;
      res.vin[i] = c.vin;
      res.alpha_rad[i] = c.alpha_rad;
    }
    const auto out = simulate_batch(model, shape, cases, params, o.engine);
    for (std::size_t i = begin; i < end; ++i) {
      res.vout[i] = out[i - begin].vout;
      res.status[i] = static_cast<int>(out[i - begin].status);
    }
    if (on_chunk) on_chunk(begin, end, res);
    bar.advance(end - begin);
  }
  bar.finish();
  res.seconds = seconds_since(t0);
  return res;
}

}  // namespace

MonteCarloResult run_monte_carlo(const Model& model, const Shape& shape,
                                 const std::vector<ParameterInput>& inputs,
                                 const MonteCarloOptions& options, const ChunkCallback& on_chunk,
                                 std::size_t first_run) {
  require_valid(options.problems(), "uq::run_monte_carlo");
  check_inputs(model, inputs);
  if (options.incident && options.incident->empty())
    throw std::invalid_argument("no incident state to resample (empty data set)");
  const RandomDraws r = draw(options.runs, inputs.size(),
                             options.incident ? options.incident->size() : 1, options.seed);
  // OpenTURNS quantiles evaluated serially here (its objects are not shared across threads).
  return simulate_runs(
      model, shape, inputs, options, r,
      [&](std::size_t k, double u) { return inputs[k].distribution.quantile(u); }, on_chunk,
      first_run);
}

MonteCarloResult run_monte_carlo(const Model& model, const Shape& shape,
                                 const std::vector<ParameterInput>& inputs,
                                 const MonteCarloOptions& options, const RandomDraws& draws) {
  require_valid(options.problems(), "uq::run_monte_carlo");
  check_inputs(model, inputs);
  return simulate_runs(
      model, shape, inputs, options, draws,
      [&](std::size_t k, double u) { return inputs[k].distribution.quantile(u); }, {}, 0);
}

namespace {

// Cramer-von Mises omega^2 of the measured points against the simulated ECDF (Anderson 1962,
// one-sample form with F = the simulated ECDF).
double cramer_von_mises(std::vector<double> sim, std::vector<double> meas) {
  if (sim.empty() || meas.empty()) return NAN;
  std::sort(sim.begin(), sim.end());
  std::sort(meas.begin(), meas.end());
  const double n = static_cast<double>(meas.size());
  double s = 0;
  for (std::size_t i = 0; i < meas.size(); ++i) {
    const double F =
        static_cast<double>(std::upper_bound(sim.begin(), sim.end(), meas[i]) - sim.begin()) /
        static_cast<double>(sim.size());
    const double d = F - (static_cast<double>(i) + 0.5) / n;
    s += d * d;
  }
  return s / n;
}

// KS statistic only (no p-value): the objective of the range calibration, cheap.
double ks_statistic(std::vector<double> a, std::vector<double> b) {
  if (a.empty() || b.empty()) return 1.0;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::size_t i = 0, j = 0;
  double d = 0;
  while (i < a.size() && j < b.size()) {
    const double x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= x) ++i;
    while (j < b.size() && b[j] <= x) ++j;
    d = std::max(d,
                 std::fabs(static_cast<double>(i) / a.size() - static_cast<double>(j) / b.size()));
  }
  return d;
}

}  // namespace

CdfComparison compare_cdfs(const MonteCarloResult& mc, const ImpactSet& measured) {
  CdfComparison c;
  const char* names[3] = {"vout_x", "vout_y", "wout"};
  for (int k = 0; k < 3; ++k) {
    const std::vector<double> sim = mc.component(k);
    const std::vector<double> meas = measured.feature(names[k]);
    const stats::KsResult ks = stats::ks_two_sample(sim, meas);
    c.ks[k] = ks.statistic;
    c.p_value[k] = ks.p_value;
    c.cvm[k] = cramer_von_mises(sim, meas);
    c.n_simulated = sim.size();
    c.n_measured = meas.size();
  }
  return c;
}

RangeFitResult calibrate_ranges(const Model& model, const Shape& shape, const ImpactSet& measured,
                                const std::vector<ParameterInput>& start,
                                const RangeFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  require_valid(options.problems(), "uq::calibrate_ranges");
  check_inputs(model, start);
  if (start.empty()) throw std::invalid_argument("calibrate_ranges: no parameter to vary");
  const std::size_t V = start.size();
  std::vector<double> blo(V), bhi(V);
  for (std::size_t k = 0; k < V; ++k) {
    const std::size_t i = model.index(start[k].name);
    blo[k] = model.lower(i);
    bhi[k] = model.upper(i);
  }
  const RandomDraws draws = draw(
      options.mc.runs, V, options.mc.incident ? options.mc.incident->size() : 1, options.mc.seed);
  const char* names[3] = {"vout_x", "vout_y", "wout"};
  std::vector<std::vector<double>> meas(3);
  for (int k = 0; k < 3; ++k) meas[k] = measured.feature(names[k]);

  // Variables: the two ends of each range in units of the bounds, in either order.
  auto ranges_of = [&](const std::vector<double>& x) {
    std::vector<ParameterInput> r;
    for (std::size_t k = 0; k < V; ++k) {
      double a = blo[k] + (bhi[k] - blo[k]) * std::min(x[2 * k], x[2 * k + 1]);
      double b = blo[k] + (bhi[k] - blo[k]) * std::max(x[2 * k], x[2 * k + 1]);
      const double min_width = 1e-6 * (bhi[k] - blo[k]);
      if (b - a < min_width) {
        b = std::min(bhi[k], a + min_width);
        a = b - min_width;
      }
      r.push_back({start[k].name, Distribution::uniform(a, b)});
    }
    return r;
  };
  struct Ctx {
    std::function<double(const std::vector<double>&)> f;
    int evals = 0;
  } ctx;
  MonteCarloOptions mc = options.mc;
  mc.progress = false;
  ctx.f = [&](const std::vector<double>& x) {
    const auto r = ranges_of(x);
    // Uniform quantiles directly: the same uniforms map to shifted values (common random
    // numbers), so the objective moves continuously with the ranges.
    const MonteCarloResult res = simulate_runs(
        model, shape, r, mc, draws,
        [&](std::size_t k, double u) {
          const double a = r[k].distribution.lower(), b = r[k].distribution.upper();
          return a + (b - a) * u;
        },
        {}, 0);
    double d = 0;
    for (int k = 0; k < 3; ++k)
      d += options.distance == RangeFitOptions::Distance::kCramerVonMises
               ? cramer_von_mises(res.component(k), meas[k])
               : ks_statistic(res.component(k), meas[k]);
    ++ctx.evals;
    return d;
  };
  std::vector<double> x(2 * V);
  for (std::size_t k = 0; k < V; ++k) {
    x[2 * k] = std::clamp((start[k].distribution.lower() - blo[k]) / (bhi[k] - blo[k]), 0.0, 1.0);
    x[2 * k + 1] =
        std::clamp((start[k].distribution.upper() - blo[k]) / (bhi[k] - blo[k]), 0.0, 1.0);
  }
  RangeFitResult out;
  out.initial_distance = ctx.f(x);
  nlopt::opt opt(nlopt::LN_SBPLX, static_cast<unsigned>(2 * V));
  opt.set_lower_bounds(std::vector<double>(2 * V, 0.0));
  opt.set_upper_bounds(std::vector<double>(2 * V, 1.0));
  opt.set_min_objective(
      [](unsigned n, const double* xs, double*, void* data) {
        return static_cast<Ctx*>(data)->f(std::vector<double>(xs, xs + n));
      },
      &ctx);
  opt.set_xtol_abs(options.xtol);
  opt.set_maxeval(options.max_evaluations);
  opt.set_initial_step(0.05);
  double f = out.initial_distance;
  std::vector<double> best = x;
  try {
    std::vector<double> y = x;
    opt.optimize(y, f);
    best = y;
  } catch (const nlopt::roundoff_limited&) {
  }
  if (!(f <= out.initial_distance)) {
    best = x;
    f = out.initial_distance;
  }
  out.ranges = ranges_of(best);
  out.distance = f;
  const MonteCarloResult res = simulate_runs(
      model, shape, out.ranges, mc, draws,
      [&](std::size_t k, double u) {
        const double a = out.ranges[k].distribution.lower(), b = out.ranges[k].distribution.upper();
        return a + (b - a) * u;
      },
      {}, 0);
  out.comparison = compare_cdfs(res, measured);
  out.evaluations = ctx.evals;
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace ricochet::uq
