// Descriptive statistics, empirical CDFs and two-sample tests on samples of reflected velocities.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace ricochet::stats {

/// Summary of one sample (paper Table 2 rows). std is the sample standard deviation (n - 1);
/// cv = std / mean (signed, as printed in Table 2).
struct Summary {
  std::size_t n = 0;
  double mean = 0, std = 0, cv = 0, min = 0, max = 0;
};
/// NaN values are skipped. An empty sample gives n = 0 and NaN fields.
Summary summarize(std::span<const double> x);

/// Empirical CDF: sorted values and cumulative probabilities i/n (i = 1..n), as the paper's
/// Figs. 9-12 draw them.
struct Ecdf {
  std::vector<double> x;
  std::vector<double> p;
};
Ecdf ecdf(std::span<const double> x);

/// Two-sample Kolmogorov-Smirnov test: statistic D = sup |F1 - F2| and its p-value
/// (computed by OpenTURNS, HypothesisTest/FittingTest two-sample Kolmogorov).
struct KsResult {
  double statistic = 0;
  double p_value = 1;
};
KsResult ks_two_sample(std::span<const double> a, std::span<const double> b);

/// Pearson correlation coefficient of paired samples (NaN pairs skipped) and its two-sided
/// p-value for H0: no correlation (t-test with n - 2 degrees of freedom).
struct Correlation {
  double r = 0;
  double p_value = 1;
  std::size_t n = 0;
};
Correlation pearson(std::span<const double> x, std::span<const double> y);

}  // namespace ricochet::stats
