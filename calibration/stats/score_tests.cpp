#include "stats/score_tests.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace ricochet::stats {
namespace {

constexpr double kNoStat = -std::numeric_limits<double>::infinity();

// The (1 - level) quantile of draws sorted ascending: the smallest draw with at most a fraction
// `level` of the draws at or above it.
double upper_quantile(const std::vector<double>& sorted, double level) {
  const auto k =
      static_cast<std::size_t>(std::ceil((1.0 - level) * static_cast<double>(sorted.size())));
  return sorted[std::min(k, sorted.size() - 1)];
}

double oriented(double t, bool two_sided) {
  return two_sided ? std::fabs(t) : t;
}

}  // namespace

ScoreTests robust_score_tests(std::span<const ScoreColumn> columns, std::size_t hypotheses,
                              const ScoreTestOptions& o) {
  ScoreTests out;
  out.statistic.assign(hypotheses, kNoStat);
  out.p_value.assign(hypotheses, 1.0);
  out.p_adjusted.assign(hypotheses, 1.0);
  if (columns.empty()) return out;
  const std::size_t n = columns.front().u.size();
  if (n <= o.nuisance + 1)
    throw std::invalid_argument("robust_score_tests: " + std::to_string(n) + " units for " +
                                std::to_string(o.nuisance) + " nuisance parameters");
  out.dof = static_cast<double>(n - o.nuisance - 1);

  // Observed statistics and the unit-norm columns the draws are made of.
  std::vector<std::vector<double>> v(columns.size());
  std::vector<bool> usable(columns.size(), false);
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const ScoreColumn& col = columns[c];
    if (col.u.size() != n)
      throw std::invalid_argument("robust_score_tests: columns differ in length");
    if (col.hypothesis >= hypotheses)
      throw std::invalid_argument("robust_score_tests: column of hypothesis " +
                                  std::to_string(col.hypothesis) + " out of range");
    // Centred: under the alternative the contributions' mean is the signal.
    const auto [s, mean, ss] = column_moments(col.u);
    double t = 0;
    if (ss > 0 && std::isfinite(ss)) {
      t = s / std::sqrt(static_cast<double>(n) * ss / out.dof);
      usable[c] = true;
      v[c].resize(n);
      for (std::size_t i = 0; i < n; ++i) v[c][i] = (col.u[i] - mean) / std::sqrt(ss);
    }
    out.t.push_back(t);
    if (usable[c])
      out.statistic[col.hypothesis] =
          std::max(out.statistic[col.hypothesis], oriented(t, col.two_sided));
  }

  // The joint null: one row of hypothesis statistics per draw.
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> normal;
  std::chi_squared_distribution<double> chi2(out.dof);
  const std::size_t B = std::max<std::size_t>(o.draws, 1);
  std::vector<double> star(B * hypotheses, kNoStat);
  std::vector<double> xi(n);
  for (std::size_t b = 0; b < B; ++b) {
    for (double& x : xi) x = normal(rng);
    const double w = std::sqrt(out.dof / chi2(rng));
    double* row = &star[b * hypotheses];
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (!usable[c]) continue;
      double t = 0;
      for (std::size_t i = 0; i < n; ++i) t += v[c][i] * xi[i];
      double& h = row[columns[c].hypothesis];
      h = std::max(h, oriented(w * t, columns[c].two_sided));
    }
  }
  out.max_null.reserve(B);
  for (std::size_t b = 0; b < B; ++b) {
    const double* row = &star[b * hypotheses];
    out.max_null.push_back(*std::max_element(row, row + hypotheses));
  }
  std::sort(out.max_null.begin(), out.max_null.end());
  // Multiple comparisons with the best (header): per hypothesis, the draws of its largest
  // deficit against any other hypothesis or the reference.
  out.mcb_critical.assign(hypotheses, NAN);
  {
    auto quantile = [&](std::vector<double>& x) {
      std::sort(x.begin(), x.end());
      return upper_quantile(x, o.mcb_level);
    };
    std::vector<double> deficit(B);
    for (std::size_t h = 0; h < hypotheses; ++h) {
      if (out.statistic[h] == kNoStat) continue;
      for (std::size_t b = 0; b < B; ++b) {
        const double* row = &star[b * hypotheses];
        double m = 0;  // the reference
        for (std::size_t k = 0; k < hypotheses; ++k)
          if (k != h && row[k] != kNoStat) m = std::max(m, row[k]);
        deficit[b] = m - row[h];
      }
      out.mcb_critical[h] = quantile(deficit);
    }
    for (std::size_t b = 0; b < B; ++b) deficit[b] = std::max(0.0, out.max_null[b]);
    out.mcb_reference_critical = quantile(deficit);
  }
  auto p_of = [&](std::size_t count) {
    return (1.0 + static_cast<double>(count)) / (1.0 + static_cast<double>(B));
  };

  // Unadjusted: each hypothesis against its own null draws.
  for (std::size_t h = 0; h < hypotheses; ++h) {
    if (out.statistic[h] == kNoStat) continue;
    std::size_t count = 0;
    for (std::size_t b = 0; b < B; ++b) count += star[b * hypotheses + h] >= out.statistic[h];
    out.p_value[h] = p_of(count);
  }

  // Step-down max-T: the suffix maxima of each draw over the hypotheses sorted by statistic.
  std::vector<std::size_t> order;
  for (std::size_t h = 0; h < hypotheses; ++h)
    if (out.statistic[h] != kNoStat) order.push_back(h);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return out.statistic[a] > out.statistic[b];
  });
  std::vector<std::size_t> count(order.size(), 0);
  for (std::size_t b = 0; b < B; ++b) {
    const double* row = &star[b * hypotheses];
    double suffix = kNoStat;
    for (std::size_t k = order.size(); k-- > 0;) {
      suffix = std::max(suffix, row[order[k]]);
      count[k] += suffix >= out.statistic[order[k]];
    }
  }
  double running = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    running = std::max(running, p_of(count[k]));
    out.p_adjusted[order[k]] = running;
  }
  return out;
}

ColumnMoments column_moments(std::span<const double> u) {
  ColumnMoments m;
  for (double x : u) m.sum += x;
  m.mean = m.sum / static_cast<double>(u.size());
  for (double x : u) m.ss += (x - m.mean) * (x - m.mean);
  return m;
}

double score_standard_error(std::span<const double> u, double dof) {
  if (!(dof > 0)) return NAN;
  return std::sqrt(static_cast<double>(u.size()) * column_moments(u).ss / dof);
}

double max_null_quantile(const ScoreTests& tests, double level) {
  if (tests.max_null.empty() || !(level > 0 && level < 1)) return NAN;
  return upper_quantile(tests.max_null, level);
}

}  // namespace ricochet::stats
