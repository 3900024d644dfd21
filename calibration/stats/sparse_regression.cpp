// Sparse regression: best subset by leak-free cross-validation over groups and the cluster
// bootstrap (sparse_regression.hpp has the method and its references).
#include "stats/sparse_regression.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <string>

#include "common/error.hpp"

namespace ricochet::stats {

namespace {

constexpr const char* kWhere = "<sparse regression design>";

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

double predict(const SparseDesign& d, std::size_t i, const std::vector<double>& c) {
  double p = 0;
  for (std::size_t j = 0; j < d.cols; ++j) p += d.x[i * d.cols + j] * c[j];
  return p;
}

void check_design(const SparseDesign& d) {
  if (d.cols == 0) throw InputError(kWhere, 0, "cols", "the design has no term");
  if (d.cols > kMaxTerms)
    throw InputError(kWhere, 0, "cols",
                     std::to_string(d.cols) + " terms; the exhaustive search takes at most " +
                         std::to_string(kMaxTerms) + " per component");
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
  check_range(p, "bootstrap", static_cast<double>(bootstrap), kBootstrap);
  check_range(p, "level", level, kLevel);
  return p;
}

std::vector<double> subset_fit(const SparseDesign& d, std::uint32_t support,
                               std::span<const std::size_t> rows) {
  std::vector<std::size_t> all;
  if (rows.empty()) {
    all.resize(d.rows());
    std::iota(all.begin(), all.end(), 0);
    rows = all;
  }
  std::vector<double> coef(d.cols, 0.0);
  std::vector<std::size_t> cols;
  for (std::size_t j = 0; j < d.cols; ++j)
    if (support >> j & 1u) cols.push_back(j);
  if (cols.empty() || rows.empty()) return coef;
  // Columns scaled to unit rms so that the rank decision does not depend on units.
  std::vector<double> scale(cols.size(), 0.0);
  for (std::size_t k = 0; k < cols.size(); ++k) {
    for (std::size_t r : rows) scale[k] += d.x[r * d.cols + cols[k]] * d.x[r * d.cols + cols[k]];
    scale[k] = std::sqrt(scale[k] / static_cast<double>(rows.size()));
  }
  Eigen::MatrixXd a(rows.size(), cols.size());
  Eigen::VectorXd b(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t k = 0; k < cols.size(); ++k)
      a(r, k) = scale[k] > 0 ? d.x[rows[r] * d.cols + cols[k]] / scale[k] : 0.0;
    b(r) = d.y[rows[r]];
  }
  const Eigen::VectorXd s = a.completeOrthogonalDecomposition().solve(b);
  for (std::size_t k = 0; k < cols.size(); ++k)
    coef[cols[k]] = scale[k] > 0 ? s(k) / scale[k] : 0.0;
  return coef;
}

std::vector<double> heldout_predictions(const SparseDesign& d, std::uint32_t support,
                                        std::span<const std::size_t> fold_of_group) {
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
    const std::vector<double> c = subset_fit(d, support, train);
    for (std::size_t i : test) pred[i] = predict(d, i, c);
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
  if (o.support && *o.support >> d.cols != 0u)  // cols <= kMaxTerms (check_design)
    throw InputError(kWhere, 0, "support",
                     "names a term beyond the design's " + std::to_string(d.cols) + " columns");
  SparseResult res;
  res.groups = groups;
  res.folds = std::min(o.folds, groups);
  std::mt19937_64 rng(o.seed);
  std::vector<std::size_t> order(groups), fold(groups);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  for (std::size_t k = 0; k < groups; ++k) fold[order[k]] = k % res.folds;
  std::vector<double> count(groups, 0.0);
  for (std::size_t i = 0; i < d.rows(); ++i) count[g[i]] += 1;

  // Every subset's cross-validated error; the best per size.
  const std::size_t p = d.cols;
  res.cv_error.assign(p + 1, INFINITY);
  res.cv_se.assign(p + 1, NAN);
  res.best_support.assign(p + 1, 0);
  std::vector<std::vector<double>> best_heldout(p + 1);
  for (std::uint32_t s = 0; s < (1u << p); ++s) {
    if (o.support && s != 0u && s != *o.support) continue;
    const auto k = static_cast<std::size_t>(std::popcount(s));
    const std::vector<double> held = heldout_predictions(d, s, fold);
    std::vector<double> mse(groups, 0.0);
    for (std::size_t i = 0; i < d.rows(); ++i)
      mse[g[i]] += (d.y[i] - held[i]) * (d.y[i] - held[i]) / count[g[i]];
    const double mean = std::accumulate(mse.begin(), mse.end(), 0.0) / static_cast<double>(groups);
    if (!(mean < res.cv_error[k])) continue;
    double ss = 0;
    for (double m : mse) ss += (m - mean) * (m - mean);
    res.cv_error[k] = mean;
    res.cv_se[k] = std::sqrt(ss / static_cast<double>(groups - 1) / static_cast<double>(groups));
    res.best_support[k] = s;
    best_heldout[k] = held;
  }
  const std::size_t best = static_cast<std::size_t>(
      std::min_element(res.cv_error.begin(), res.cv_error.end()) - res.cv_error.begin());
  res.size = best;
  if (o.support)
    res.size = static_cast<std::size_t>(std::popcount(*o.support));
  else
    for (std::size_t k = 0; k <= best; ++k)
      if (res.cv_error[k] <= res.cv_error[best] + res.cv_se[best]) {
        res.size = k;
        break;
      }
  const std::uint32_t chosen = res.best_support[res.size];
  res.heldout = best_heldout[res.size];
  res.coef = subset_fit(d, chosen);
  res.active.resize(p);
  for (std::size_t j = 0; j < p; ++j) res.active[j] = chosen >> j & 1u;

  res.lo.assign(p, NAN);
  res.hi.assign(p, NAN);
  res.inclusion.assign(p, NAN);
  if (o.bootstrap == 0) return res;
  std::vector<std::vector<std::size_t>> members(groups);
  for (std::size_t i = 0; i < d.rows(); ++i) members[g[i]].push_back(i);
  std::uniform_int_distribution<std::size_t> pick(0, groups - 1);
  std::vector<std::vector<double>> draws(p);
  std::vector<double> in(p, 0.0);
  for (std::size_t b = 0; b < o.bootstrap; ++b) {
    std::vector<std::size_t> rows;
    for (std::size_t k = 0; k < groups; ++k) {
      const auto& m = members[pick(rng)];
      rows.insert(rows.end(), m.begin(), m.end());
    }
    // The selection's stability: the best subset of the chosen size on this resample, by its
    // in-sample error (the named support itself when there is one).
    std::uint32_t reselected = chosen;
    if (!o.support) {
      double sse_best = INFINITY;
      for (std::uint32_t s = 0; s < (1u << p); ++s) {
        if (static_cast<std::size_t>(std::popcount(s)) != res.size) continue;
        const std::vector<double> cs = subset_fit(d, s, rows);
        double sse = 0;
        for (std::size_t i : rows) {
          const double e = d.y[i] - predict(d, i, cs);
          sse += e * e;
        }
        if (sse < sse_best) {
          sse_best = sse;
          reselected = s;
        }
      }
    }
    // The constants' uncertainty: the chosen law refitted on the resample.
    const std::vector<double> c = subset_fit(d, chosen, rows);
    for (std::size_t j = 0; j < p; ++j) {
      if (chosen >> j & 1u) draws[j].push_back(c[j]);
      in[j] += reselected >> j & 1u ? 1.0 : 0.0;
    }
  }
  const double tail = (1 - o.level) / 2;
  for (std::size_t j = 0; j < p; ++j) {
    res.inclusion[j] = in[j] / static_cast<double>(o.bootstrap);
    if (draws[j].empty()) continue;
    std::sort(draws[j].begin(), draws[j].end());
    res.lo[j] = percentile(draws[j], tail);
    res.hi[j] = percentile(draws[j], 1 - tail);
  }
  return res;
}

}  // namespace ricochet::stats
