#include "uq/sobol.hpp"

#include <openturns/OT.hxx>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "common/clock.hpp"
#include "fit/design.hpp"

namespace ricochet::uq {

const char* estimator_name(SobolEstimator e) {
  switch (e) {
    case SobolEstimator::kSaltelli:
      return "saltelli";
    case SobolEstimator::kJansen:
      return "jansen";
    case SobolEstimator::kMartinez:
      return "martinez";
    case SobolEstimator::kMauntzKucherenko:
      return "mauntz-kucherenko";
  }
  return "?";
}

SobolEstimator parse_estimator(const std::string& name) {
  for (auto e : {SobolEstimator::kSaltelli, SobolEstimator::kJansen, SobolEstimator::kMartinez,
                 SobolEstimator::kMauntzKucherenko})
    if (name == estimator_name(e)) return e;
  throw std::invalid_argument("unknown Sobol estimator '" + name +
                              "'; known: saltelli, jansen, martinez, mauntz-kucherenko");
}

namespace {

OT::SobolIndicesAlgorithm make_algorithm(SobolEstimator e, const OT::Sample& x, const OT::Sample& y,
                                         std::size_t n) {
  switch (e) {
    case SobolEstimator::kSaltelli:
      return OT::SaltelliSensitivityAlgorithm(x, y, n);
    case SobolEstimator::kJansen:
      return OT::JansenSensitivityAlgorithm(x, y, n);
    case SobolEstimator::kMartinez:
      return OT::MartinezSensitivityAlgorithm(x, y, n);
    case SobolEstimator::kMauntzKucherenko:
      return OT::MauntzKucherenkoSensitivityAlgorithm(x, y, n);
  }
  throw std::invalid_argument("unknown estimator");
}

// Percentile interval of bootstrap values.
std::pair<double, double> percentile(std::vector<double> v, double confidence) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return {NAN, NAN};
  std::sort(v.begin(), v.end());
  auto at = [&](double p) {
    const double pos = p * static_cast<double>(v.size() - 1);
    const std::size_t i = static_cast<std::size_t>(std::floor(pos));
    const double w = pos - static_cast<double>(i);
    return i + 1 < v.size() ? v[i] * (1 - w) + v[i + 1] * w : v[i];
  };
  return {at(0.5 * (1.0 - confidence)), at(0.5 * (1.0 + confidence))};
}

}  // namespace

SobolResult sobol_indices(const BatchFunction& f, const std::vector<ParameterInput>& inputs,
                          const std::vector<std::string>& outputs, const SobolOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t d = inputs.size(), p = outputs.size(), N = options.base_size;
  require_valid(options.problems(), "uq::sobol_indices");
  if (d < 2) throw std::invalid_argument("Sobol indices need at least two varied inputs");
  // The design (and, below, OpenTURNS' own bootstrap) draw from OpenTURNS' global generator.
  std::unique_lock<std::mutex> lock(fit::openturns_rng_mutex());
  OT::RandomGenerator::SetSeed(options.seed);
  // The design is drawn on the unit cube and mapped through each input's inverse CDF below
  // (independent inputs): the same pick-freeze structure for any marginal.
  const OT::ComposedDistribution unit(
      OT::ComposedDistribution::DistributionCollection(d, OT::Uniform(0.0, 1.0)));
  const OT::SobolIndicesExperiment experiment(unit, N, true);
  const OT::Sample u = experiment.generate();
  lock.unlock();
  const std::size_t rows = u.getSize();
  std::vector<double> x(rows * d);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t k = 0; k < d; ++k) x[r * d + k] = inputs[k].distribution.quantile(u(r, k));
  std::vector<double> y;
  f(x, rows, y);
  if (y.size() != rows * p) throw std::logic_error("Sobol model returned the wrong output size");

  OT::Sample xs(rows, d);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t k = 0; k < d; ++k) xs(r, k) = x[r * d + k];
  OT::Description names;
  for (const auto& in : inputs) names.add(in.name);
  xs.setDescription(names);

  SobolResult res;
  for (const auto& in : inputs) res.inputs.push_back(in.name);
  res.outputs = outputs;
  res.base_size = N;
  res.evaluations = rows;
  res.estimator = estimator_name(options.estimator);
  res.confidence = options.confidence;
  res.first.assign(p, std::vector<Index>(d));
  res.total.assign(p, std::vector<Index>(d));
  res.second.assign(p, std::vector<std::vector<Index>>(d, std::vector<Index>(d)));
  res.variance.assign(p, 0.0);
  res.design_x = x;
  res.design_y = y;
  const std::size_t blocks = rows / N;  // 2 d + 2 with second order

  lock.lock();
  for (std::size_t o = 0; o < p; ++o) {
    OT::Sample ys(rows, 1);
    for (std::size_t r = 0; r < rows; ++r) ys(r, 0) = y[r * p + o];
    res.variance[o] = ys.computeVariance()[0];
    OT::RandomGenerator::SetSeed(options.seed + 1 + o);
    OT::SobolIndicesAlgorithm algo = make_algorithm(options.estimator, xs, ys, N);
    algo.setBootstrapSize(options.bootstrap);
    algo.setConfidenceLevel(options.confidence);
    const OT::Point s1 = algo.getFirstOrderIndices(0);
    const OT::Point st = algo.getTotalOrderIndices(0);
    const OT::Interval i1 = algo.getFirstOrderIndicesInterval();
    const OT::Interval it = algo.getTotalOrderIndicesInterval();
    const OT::SymmetricMatrix s2 = algo.getSecondOrderIndices(0);
    for (std::size_t i = 0; i < d; ++i) {
      res.first[o][i] = {s1[i], i1.getLowerBound()[i], i1.getUpperBound()[i]};
      res.total[o][i] = {st[i], it.getLowerBound()[i], it.getUpperBound()[i]};
      for (std::size_t j = i + 1; j < d; ++j) res.second[o][i][j].value = s2(i, j);
    }
    // Second-order intervals: OpenTURNS has none, so bootstrap the rows of the design (the same
    // row index in every block, as OpenTURNS' own bootstrap) and re-run its estimator.
    std::vector<std::vector<std::vector<double>>> boot(d, std::vector<std::vector<double>>(d));
    OT::RandomGenerator::SetSeed(options.seed + 1000 + o);
    for (std::size_t b = 0; b < options.bootstrap; ++b) {
      const OT::RandomGenerator::UnsignedIntegerCollection pick =
          OT::RandomGenerator::IntegerGenerate(N, N);
      OT::Sample xb(rows, d), yb(rows, 1);
      for (std::size_t blk = 0; blk < blocks; ++blk)
        for (std::size_t r = 0; r < N; ++r) {
          const std::size_t from = blk * N + pick[r], to = blk * N + r;
          for (std::size_t k = 0; k < d; ++k) xb(to, k) = xs(from, k);
          yb(to, 0) = ys(from, 0);
        }
      const OT::SymmetricMatrix sb =
          make_algorithm(options.estimator, xb, yb, N).getSecondOrderIndices(0);
      for (std::size_t i = 0; i < d; ++i)
        for (std::size_t j = i + 1; j < d; ++j) boot[i][j].push_back(sb(i, j));
    }
    for (std::size_t i = 0; i < d; ++i)
      for (std::size_t j = i + 1; j < d; ++j) {
        const auto [lo, hi] = percentile(boot[i][j], options.confidence);
        res.second[o][i][j].lo = lo;
        res.second[o][i][j].hi = hi;
        res.second[o][j][i] = res.second[o][i][j];
      }
  }
  lock.unlock();
  res.seconds = seconds_since(t0);
  return res;
}

SobolResult collision_sobol(const Model& model, const Shape& shape,
                            const std::vector<ParameterInput>& inputs, const Vel3& vin,
                            double alpha_rad, const SobolOptions& options,
                            const EngineOptions& engine) {
  OptionProblems problems = options.problems();
  append_nested(problems, "engine", engine.problems());
  require_valid(problems, "uq::collision_sobol");
  std::vector<std::size_t> index;
  for (const auto& in : inputs) index.push_back(model.index(in.name));
  const std::size_t P = model.parameter_count(), d = inputs.size();
  BatchFunction f = [&](const std::vector<double>& x, std::size_t n, std::vector<double>& y) {
    std::vector<CollisionCase> cases(n, CollisionCase{vin, shape.is_disc() ? 0.0 : alpha_rad});
    std::vector<double> params(n * P);
    for (std::size_t r = 0; r < n; ++r) {
      std::copy(model.values().begin(), model.values().end(), params.begin() + r * P);
      for (std::size_t k = 0; k < d; ++k) params[r * P + index[k]] = x[r * d + k];
    }
    const auto out = simulate_batch(model, shape, cases, params, engine);
    y.resize(n * 3);
    for (std::size_t r = 0; r < n; ++r)
      for (int k = 0; k < 3; ++k) y[r * 3 + k] = out[r].vout[k];
  };
  return sobol_indices(f, inputs, {"vx", "vy", "w"}, options);
}

IshigamiIndices ishigami_analytic(double a, double b) {
  const double pi4 = std::pow(M_PI, 4), pi8 = std::pow(M_PI, 8);
  const double v1 = 0.5 * std::pow(1.0 + b * pi4 / 5.0, 2);
  const double v2 = a * a / 8.0;
  const double v13 = b * b * pi8 * (1.0 / 18.0 - 1.0 / 50.0);
  const double v = v1 + v2 + v13;
  return {{v1 / v, v2 / v, 0.0}, {(v1 + v13) / v, v2 / v, v13 / v}, v13 / v};
}

BatchFunction ishigami(double a, double b) {
  return [a, b](const std::vector<double>& x, std::size_t n, std::vector<double>& y) {
    y.resize(n);
    for (std::size_t r = 0; r < n; ++r) {
      const double x1 = x[3 * r], x2 = x[3 * r + 1], x3 = x[3 * r + 2];
      y[r] = std::sin(x1) + a * std::sin(x2) * std::sin(x2) + b * std::pow(x3, 4) * std::sin(x1);
    }
  };
}

}  // namespace ricochet::uq
