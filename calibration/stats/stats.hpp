// Descriptive statistics, empirical CDFs and two-sample tests on samples of reflected velocities.
#pragma once

#include <cstddef>
#include <cstdint>
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

/// The two-sample KS test of exact model values against measurements that carry a measurement
/// noise the model values do not (e.g. resolved V_out against the lab's, read from video):
/// each of `draws` draws adds independent Gaussian noise of standard deviation `sigma` (the
/// measured quantity's unit) to the model values and runs ks_two_sample against `measured`.
/// The noise comes from std::mt19937_64(seed) by Box-Muller, so a seed gives the same result on
/// every machine. sigma = 0 gives ks_two_sample's p for every draw. It says whether noise of
/// that size can account for a narrower model spread, not that the model has the measurements'
/// scatter. Throws std::invalid_argument for sigma < 0 or not finite, draws = 0, an empty sample.
struct NoisyKsResult {
  double sigma = 0;
  std::size_t draws = 0;
  double median_p = 1;           ///< median p-value over the draws
  double p10 = 1;                ///< 10th percentile of the p-values
  double share_p_above_005 = 1;  ///< share of draws with p > 0.05
};
NoisyKsResult ks_with_measurement_noise(std::span<const double> model,
                                        std::span<const double> measured, double sigma,
                                        std::size_t draws, std::uint64_t seed);

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

/// Upper tail P(T > t) of Student's t distribution with `dof` degrees of freedom (OpenTURNS
/// DistFunc). dof must be positive.
double student_t_upper_tail(double t, double dof);

/// Upper tail P(X > x) of the chi-square distribution with `dof` degrees of freedom.
double chi_square_upper_tail(double x, double dof);

/// Holm's step-down adjustment (Holm 1979, Scand. J. Statist. 6:65): adjusted p-values that
/// control the family-wise error rate over the whole family, in the input order. NaN p-values
/// count as 1 and stay NaN. `family_size` >= p.size() counts hypotheses that were not tested
/// (p = 1, e.g. candidates screened out); 0 means p.size().
std::vector<double> holm_adjust(std::span<const double> p, std::size_t family_size = 0);

/// Corrected resampled t-test (Nadeau & Bengio 2003, Machine Learning 52:239; Bouckaert & Frank
/// 2004 for repeated k-fold): `d` holds one mean difference per train/test split (J splits, each
/// with n_test test and n_train training releases). The splits share training data, so the
/// variance of the mean is (1/J + n_test/n_train) s^2 rather than s^2 / J.
///   t = mean(d) / sqrt((1/J + n_test/n_train) s^2),  dof = J - 1.
struct ResampledTest {
  double mean = 0;
  double se = 0;  ///< corrected standard error of the mean
  double t = 0;
  double p_value = 1;  ///< one-sided, H0: mean <= 0
  std::size_t splits = 0;
};
ResampledTest corrected_resampled_t(std::span<const double> d, double n_test, double n_train);

/// Wilson score interval of a binomial proportion (successes out of n) at two-sided level
/// 1 - alpha (Wilson 1927, JASA 22:209). n = 0 gives [0, 1].
struct Proportion {
  double rate = 0, lo = 0, hi = 1;
};
Proportion wilson(std::size_t successes, std::size_t n, double alpha = 0.05);
/// Clopper-Pearson ("exact") interval of the same proportion (Clopper & Pearson 1934, Biometrika
/// 26:404): lo = Beta^-1(alpha/2; k, n - k + 1), hi = Beta^-1(1 - alpha/2; k + 1, n - k), lo = 0
/// at k = 0 and hi = 1 at k = n. Its coverage is at least 1 - alpha for every true rate, at the
/// price of width: the choice of a reading fixed before its data, where Wilson's near-nominal
/// coverage can fall below it for small n. n = 0 gives [0, 1].
Proportion clopper_pearson(std::size_t successes, std::size_t n, double alpha = 0.05);

}  // namespace ricochet::stats
