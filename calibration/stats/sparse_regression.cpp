// Sparse regression: STLSQ, leak-free cross-validation and the cluster bootstrap over groups
// (sparse_regression.hpp has the method and its references).
#include "stats/sparse_regression.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>

#include "common/error.hpp"

namespace ricochet::stats {

namespace {

constexpr const char* kWhere = "<sparse regression design>";

double rms_of(const SparseDesign& d, std::span<const std::size_t> rows, std::size_t col,
              bool response) {
  double s = 0;
  for (std::size_t r : rows) {
    const double v = response ? d.y[r] : d.x[r * d.cols + col];
    s += v * v;
  }
  return rows.empty() ? 0.0 : std::sqrt(s / static_cast<double>(rows.size()));
}

// Dense group index of every sample, in order of first appearance, and the number of groups.
std::pair<std::vector<std::size_t>, std::size_t> dense_groups(const SparseDesign& d) {
  std::map<std::size_t, std::size_t> index;
  std::vector<std::size_t> g(d.rows());
  for (std::size_t i = 0; i < d.rows(); ++i)
    g[i] = index.emplace(d.group[i], index.size()).first->second;
  return {g, index.size()};
}

// Percentile of sorted values (linear interpolation between order statistics, Hyndman & Fan
// 1996 type 7).
double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return NAN;
  const double h = q * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

void check_design(const SparseDesign& d) {
  if (d.cols == 0) throw InputError(kWhere, 0, "cols", "the design has no term");
  if (d.x.size() != d.rows() * d.cols)
    throw InputError(kWhere, 0, "x",
                     "holds " + std::to_string(d.x.size()) + " values, expected rows x cols = " +
                         std::to_string(d.rows()) + " x " + std::to_string(d.cols));
  if (d.group.size() != d.rows())
    throw InputError(kWhere, 0, "group",
                     "holds " + std::to_string(d.group.size()) + " ids for " +
                         std::to_string(d.rows()) + " samples");
  for (std::size_t i = 0; i < d.x.size(); ++i)
    if (!std::isfinite(d.x[i]))
      throw InputError(kWhere, 0, "x",
                       "term " + std::to_string(i % d.cols) + " at sample " +
                           std::to_string(i / d.cols) + " is not finite");
  for (std::size_t i = 0; i < d.rows(); ++i)
    if (!std::isfinite(d.y[i]))
      throw InputError(kWhere, 0, "y", "sample " + std::to_string(i) + " is not finite");
}

}  // namespace

OptionProblems SparseOptions::problems() const {
  OptionProblems p;
  check_range(p, "folds", static_cast<double>(folds), kFolds);
  check_range(p, "grid", static_cast<double>(grid), kGrid);
  check_range(p, "tau_min", tau_min, kTau);
  check_range(p, "tau_max", tau_max, kTau);
  if (!(tau_min < tau_max)) p.push_back({"tau_max", "must be above tau_min"});
  check_range(p, "bootstrap", static_cast<double>(bootstrap), kBootstrap);
  check_range(p, "level", level, kLevel);
  check_range(p, "max_iterations", static_cast<double>(max_iterations), kIterations);
  return p;
}

std::vector<double> stlsq(const SparseDesign& d, double tau, std::size_t max_iterations,
                          std::span<const std::size_t> rows) {
  std::vector<std::size_t> all;
  if (rows.empty()) {
    all.resize(d.rows());
    std::iota(all.begin(), all.end(), 0);
    rows = all;
  }
  std::vector<double> coef(d.cols, 0.0);
  const double rms_y = rms_of(d, rows, 0, true);
  if (!(rms_y > 0) || std::isinf(tau)) return coef;
  std::vector<double> rms_x(d.cols);
  std::vector<bool> active(d.cols);
  for (std::size_t j = 0; j < d.cols; ++j) {
    rms_x[j] = rms_of(d, rows, j, false);
    active[j] = rms_x[j] > 0;  // a term that is zero on these samples says nothing
  }
  for (std::size_t it = 0; it < max_iterations; ++it) {
    std::vector<std::size_t> cols;
    for (std::size_t j = 0; j < d.cols; ++j)
      if (active[j]) cols.push_back(j);
    std::fill(coef.begin(), coef.end(), 0.0);
    if (cols.empty()) return coef;
    // Columns scaled to unit rms so that the QR's rank decision does not depend on units.
    Eigen::MatrixXd a(rows.size(), cols.size());
    Eigen::VectorXd b(rows.size());
    for (std::size_t r = 0; r < rows.size(); ++r) {
      for (std::size_t k = 0; k < cols.size(); ++k)
        a(r, k) = d.x[rows[r] * d.cols + cols[k]] / rms_x[cols[k]];
      b(r) = d.y[rows[r]];
    }
    const Eigen::VectorXd s = a.colPivHouseholderQr().solve(b);
    bool changed = false;
    for (std::size_t k = 0; k < cols.size(); ++k) {
      coef[cols[k]] = s(k) / rms_x[cols[k]];
      const bool keep = std::abs(s(k)) / rms_y >= tau;
      if (!keep) {
        active[cols[k]] = false;
        changed = true;
      }
    }
    if (!changed) return coef;
  }
  // The support did not settle: the last refit's coefficients outside the support are zeroed.
  for (std::size_t j = 0; j < d.cols; ++j)
    if (!active[j]) coef[j] = 0;
  return coef;
}

std::vector<double> heldout_predictions(const SparseDesign& d, double tau,
                                        std::span<const std::size_t> fold_of_group,
                                        std::size_t max_iterations) {
  const auto [g, groups] = dense_groups(d);
  if (fold_of_group.size() != groups)
    throw InputError(
        kWhere, 0, "fold_of_group",
        std::to_string(fold_of_group.size()) + " folds for " + std::to_string(groups) + " groups");
  const std::size_t folds = *std::max_element(fold_of_group.begin(), fold_of_group.end()) + 1;
  std::vector<double> pred(d.rows(), NAN);
  for (std::size_t f = 0; f < folds; ++f) {
    std::vector<std::size_t> train, test;
    for (std::size_t i = 0; i < d.rows(); ++i)
      (fold_of_group[g[i]] == f ? test : train).push_back(i);
    if (test.empty()) continue;
    const std::vector<double> c = stlsq(d, tau, max_iterations, train);
    for (std::size_t i : test) {
      double p = 0;
      for (std::size_t j = 0; j < d.cols; ++j) p += d.x[i * d.cols + j] * c[j];
      pred[i] = p;
    }
  }
  return pred;
}

SparseResult sparse_regression(const SparseDesign& d, const SparseOptions& o) {
  require_valid(o.problems(), "sparse_regression");
  check_design(d);
  const auto [g, groups] = dense_groups(d);
  if (groups < 2)
    throw InputError(kWhere, 0, "group",
                     "cross-validation needs two groups at least, found " + std::to_string(groups));
  SparseResult res;
  res.groups = groups;
  res.folds = std::min(o.folds, groups);
  std::mt19937_64 rng(o.seed);
  std::vector<std::size_t> order(groups), fold(groups);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  for (std::size_t k = 0; k < groups; ++k) fold[order[k]] = k % res.folds;

  res.taus.push_back(0.0);
  for (std::size_t k = 0; k < o.grid; ++k) {
    const double u = o.grid == 1 ? 0.0 : static_cast<double>(k) / static_cast<double>(o.grid - 1);
    res.taus.push_back(o.tau_min * std::pow(o.tau_max / o.tau_min, u));
  }
  res.taus.push_back(std::numeric_limits<double>::infinity());

  std::vector<std::vector<double>> held(res.taus.size());
  std::vector<double> count(groups, 0.0);
  for (std::size_t i = 0; i < d.rows(); ++i) count[g[i]] += 1;
  for (std::size_t t = 0; t < res.taus.size(); ++t) {
    held[t] = heldout_predictions(d, res.taus[t], fold, o.max_iterations);
    std::vector<double> mse(groups, 0.0);
    for (std::size_t i = 0; i < d.rows(); ++i)
      mse[g[i]] += (d.y[i] - held[t][i]) * (d.y[i] - held[t][i]) / count[g[i]];
    const double mean = std::accumulate(mse.begin(), mse.end(), 0.0) / static_cast<double>(groups);
    double ss = 0;
    for (double m : mse) ss += (m - mean) * (m - mean);
    res.cv_error.push_back(mean);
    res.cv_se.push_back(std::sqrt(ss / static_cast<double>(groups - 1)) /
                        std::sqrt(static_cast<double>(groups)));
  }
  res.cv_error_empty = res.cv_error.back();
  const std::size_t best = static_cast<std::size_t>(
      std::min_element(res.cv_error.begin(), res.cv_error.end()) - res.cv_error.begin());
  std::size_t chosen = best;
  for (std::size_t t = best; t < res.taus.size(); ++t)
    if (res.cv_error[t] <= res.cv_error[best] + res.cv_se[best]) chosen = t;
  res.tau = res.taus[chosen];
  res.heldout = held[chosen];
  res.coef = stlsq(d, res.tau, o.max_iterations);
  res.active.resize(d.cols);
  for (std::size_t j = 0; j < d.cols; ++j) res.active[j] = res.coef[j] != 0.0;

  res.lo.assign(d.cols, NAN);
  res.hi.assign(d.cols, NAN);
  res.inclusion.assign(d.cols, NAN);
  if (o.bootstrap == 0) return res;
  std::vector<std::vector<std::size_t>> members(groups);
  for (std::size_t i = 0; i < d.rows(); ++i) members[g[i]].push_back(i);
  std::uniform_int_distribution<std::size_t> pick(0, groups - 1);
  std::vector<std::vector<double>> draws(d.cols);
  std::vector<double> in(d.cols, 0.0);
  for (std::size_t b = 0; b < o.bootstrap; ++b) {
    std::vector<std::size_t> rows;
    for (std::size_t k = 0; k < groups; ++k) {
      const auto& m = members[pick(rng)];
      rows.insert(rows.end(), m.begin(), m.end());
    }
    const std::vector<double> c = stlsq(d, res.tau, o.max_iterations, rows);
    for (std::size_t j = 0; j < d.cols; ++j) {
      draws[j].push_back(c[j]);
      in[j] += c[j] != 0.0 ? 1.0 : 0.0;
    }
  }
  const double tail = (1 - o.level) / 2;
  for (std::size_t j = 0; j < d.cols; ++j) {
    std::sort(draws[j].begin(), draws[j].end());
    res.lo[j] = percentile(draws[j], tail);
    res.hi[j] = percentile(draws[j], 1 - tail);
    res.inclusion[j] = in[j] / static_cast<double>(o.bootstrap);
  }
  return res;
}

}  // namespace ricochet::stats
