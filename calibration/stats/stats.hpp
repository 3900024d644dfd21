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
/// Figs. 9-12 draw them. NaN values are skipped.
struct Ecdf {
  std::vector<double> x;
  std::vector<double> p;
};
Ecdf ecdf(std::span<const double> x);

/// Two-sample Kolmogorov-Smirnov test: statistic D = sup |F1 - F2| and its p-value
/// (computed by OpenTURNS, HypothesisTest::TwoSamplesKolmogorov: the p-value is the exact
/// one-sample Kolmogorov tail at the effective size floor(n1 n2 / (n1 + n2))). NaN values are
/// skipped; throws std::invalid_argument if a sample is empty. Cost O((n1 + n2)^2) in
/// OpenTURNS 1.20: about 4 s for 28 against 50,000 values.
struct KsResult {
  double statistic = 0;
  double p_value = 1;
};
KsResult ks_two_sample(std::span<const double> a, std::span<const double> b);

/// Pearson correlation coefficient of paired samples (NaN pairs skipped) and its two-sided
/// p-value for H0: no correlation (t-test with n - 2 degrees of freedom, OpenTURNS
/// HypothesisTest::Pearson). r and p_value are NaN with fewer than 3 pairs or a constant sample.
/// Throws std::invalid_argument if x and y differ in size.
struct Correlation {
  double r = 0;
  double p_value = 1;
  std::size_t n = 0;
};
Correlation pearson(std::span<const double> x, std::span<const double> y);

}  // namespace ricochet::stats
