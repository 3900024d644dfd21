// Summaries, empirical CDFs, the two-sample Kolmogorov-Smirnov test and the Pearson test, each
// checked against an independent computation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "impact/impact_set.hpp"
#include "stats/stats.hpp"

#include <openturns/OT.hxx>

namespace ricochet {
namespace {

const double kNaN = std::nan("");
const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

TEST(Summarize, SampleStandardDeviationUsesNMinusOne) {
  const std::vector<double> x = {1, 2, 3, 4};
  const auto s = stats::summarize(x);
  EXPECT_EQ(s.n, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(5.0 / 3.0));  // sum of squares 5 over n - 1 = 3
  EXPECT_DOUBLE_EQ(s.cv, std::sqrt(5.0 / 3.0) / 2.5);
  EXPECT_EQ(s.min, 1);
  EXPECT_EQ(s.max, 4);
}

TEST(Summarize, SignedCvSkipsNanAndHandlesTinySamples) {
  const std::vector<double> x = {-2, kNaN, -4};
  const auto s = stats::summarize(x);
  EXPECT_EQ(s.n, 2u);
  EXPECT_DOUBLE_EQ(s.mean, -3);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(2.0));
  EXPECT_LT(s.cv, 0);  // signed, as Table 2 prints it
  const auto one = stats::summarize(std::vector<double>{5});
  EXPECT_EQ(one.n, 1u);
  EXPECT_EQ(one.mean, 5);
  EXPECT_TRUE(std::isnan(one.std));
  const auto none = stats::summarize(std::vector<double>{kNaN});
  EXPECT_EQ(none.n, 0u);
  EXPECT_TRUE(std::isnan(none.mean) && std::isnan(none.min) && std::isnan(none.max));
}

TEST(Summarize, NoCancellationForLargeOffsets) {
  // The same spread around 1e9 and around 0 must give the same std.
  std::vector<double> a, b;
  for (int i = 0; i < 100; ++i) {
    a.push_back(1e9 + 0.01 * i);
    b.push_back(0.01 * i);
  }
  EXPECT_NEAR(stats::summarize(a).std, stats::summarize(b).std, 1e-6);
}

TEST(Ecdf, SortedWithStepsOfOneOverN) {
  const std::vector<double> x = {3, kNaN, 1, 2, 2};
  const auto e = stats::ecdf(x);
  EXPECT_EQ(e.x, (std::vector<double>{1, 2, 2, 3}));
  EXPECT_EQ(e.p, (std::vector<double>{0.25, 0.5, 0.75, 1.0}));
}

// D = sup_x |F_a(x) - F_b(x)| evaluated at every pooled point, with right-continuous ECDFs
// (ties between and within samples count fully).
double brute_force_ks(std::vector<double> a, std::vector<double> b) {
  std::vector<double> pooled = a;
  pooled.insert(pooled.end(), b.begin(), b.end());
  double d = 0;
  for (double x : pooled) {
    const double fa =
        static_cast<double>(std::count_if(a.begin(), a.end(), [&](double v) { return v <= x; })) /
        static_cast<double>(a.size());
    const double fb =
        static_cast<double>(std::count_if(b.begin(), b.end(), [&](double v) { return v <= x; })) /
        static_cast<double>(b.size());
    d = std::max(d, std::abs(fa - fb));
  }
  return d;
}

// Kolmogorov's limiting tail Q(lambda) = 2 sum (-1)^(k-1) exp(-2 k^2 lambda^2), with Stephens'
// finite-size correction lambda = (sqrt(ne) + 0.12 + 0.11 / sqrt(ne)) D (Numerical Recipes 14.3).
double kolmogorov_tail(double d, double ne) {
  const double lambda = (std::sqrt(ne) + 0.12 + 0.11 / std::sqrt(ne)) * d;
  double q = 0;
  for (int k = 1; k <= 100; ++k)
    q += 2.0 * ((k % 2) ? 1.0 : -1.0) * std::exp(-2.0 * k * k * lambda * lambda);
  return q;
}

TEST(KolmogorovSmirnov, IdenticalSamples) {
  const std::vector<double> a = {0.3, 1.2, -0.7, 2.2, 0.9, 1.1};
  const auto r = stats::ks_two_sample(a, a);
  EXPECT_EQ(r.statistic, 0.0);
  EXPECT_DOUBLE_EQ(r.p_value, 1.0);
}

TEST(KolmogorovSmirnov, DisjointSamples) {
  std::vector<double> a, b;
  for (int i = 0; i < 20; ++i) {
    a.push_back(i);
    b.push_back(100 + i);
  }
  const auto r = stats::ks_two_sample(a, b);
  EXPECT_EQ(r.statistic, 1.0);
  EXPECT_LT(r.p_value, 1e-4);
}

TEST(KolmogorovSmirnov, StatisticMatchesBruteForceWithTies) {
  // The lab samples have ties within and between samples (e.g. 3.05 m/s).
  const ImpactSet cyl = read_impact_set(kLab + "cylinders.csv");
  const ImpactSet tri = read_impact_set(kLab + "triangles.csv");
  for (const char* name : {"vin_x", "vout_x", "vin_y", "vout_y", "win", "wout"}) {
    SCOPED_TRACE(name);
    const auto a = cyl.feature(name);
    const auto b = tri.feature(name);
    const auto r = stats::ks_two_sample(a, b);
    EXPECT_DOUBLE_EQ(r.statistic, brute_force_ks(a, b));
    EXPECT_GE(r.p_value, 0.0);
    EXPECT_LE(r.p_value, 1.0);
  }
  // Incident against reflected horizontal velocity of the cylinders: the shift of paper Fig. 11.
  const auto r = stats::ks_two_sample(cyl.feature("vin_x"), cyl.feature("vout_x"));
  EXPECT_DOUBLE_EQ(r.statistic, brute_force_ks(cyl.feature("vin_x"), cyl.feature("vout_x")));
}

TEST(KolmogorovSmirnov, PValueFollowsKolmogorovDistribution) {
  // Two shifted uniform grids of 200 points, effective size 200*200/400 = 100.
  std::vector<double> a, b;
  for (int i = 0; i < 200; ++i) {
    a.push_back((i + 0.5) / 200.0);
    b.push_back((i + 0.5) / 200.0 + 0.1 + 1e-9);
  }
  const auto r = stats::ks_two_sample(a, b);
  EXPECT_DOUBLE_EQ(r.statistic, brute_force_ks(a, b));
  EXPECT_NEAR(r.statistic, 0.105, 1e-12);  // 21 grid steps: the shift plus one step
  EXPECT_NEAR(r.p_value, kolmogorov_tail(r.statistic, 100), 0.01);
  EXPECT_GT(r.p_value, 0.1);
  EXPECT_LT(r.p_value, 0.3);
  // A larger shift is more significant.
  for (double& v : b) v += 0.1;
  EXPECT_LT(stats::ks_two_sample(a, b).p_value, r.p_value);
}

TEST(KolmogorovSmirnov, SkipsNanAndRefusesEmptySamples) {
  const std::vector<double> a = {1, 2, kNaN, 3};
  const std::vector<double> b = {1, 2, 3};
  EXPECT_EQ(stats::ks_two_sample(a, b).statistic, 0.0);
  EXPECT_THROW(stats::ks_two_sample(std::vector<double>{kNaN}, b), std::invalid_argument);
  EXPECT_THROW(stats::ks_two_sample(std::vector<double>{}, b), std::invalid_argument);
}

// Normal quantiles at (i + 0.5) / n: a sample with no sampling noise of its own.
std::vector<double> normal_quantiles(int n, double sd) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(sd * OT::DistFunc::qNormal((i + 0.5) / n));
  return v;
}

TEST(KolmogorovSmirnovWithNoise, NoiseOfTheRightSizeReconcilesANarrowModel) {
  // Exact model values N(0, 1); measurements N(0, 1 + 3^2): noise of sd 3 on the model makes the
  // two distributions equal, no noise leaves the model too narrow, four times that noise makes
  // it too wide. 200 values each, 200 draws.
  const auto model = normal_quantiles(200, 1.0);
  const auto measured = normal_quantiles(200, std::sqrt(10.0));
  const double plain = stats::ks_two_sample(model, measured).p_value;
  ASSERT_LT(plain, 0.01);
  const auto none = stats::ks_with_measurement_noise(model, measured, 0.0, 50, 1);
  EXPECT_EQ(none.median_p, plain);
  EXPECT_EQ(none.p10, plain);
  const auto right = stats::ks_with_measurement_noise(model, measured, 3.0, 200, 1);
  EXPECT_GT(right.median_p, 0.3);
  EXPECT_GT(right.share_p_above_005, 0.85);
  EXPECT_LE(right.p10, right.median_p);
  EXPECT_EQ(right.draws, 200u);
  const auto wide = stats::ks_with_measurement_noise(model, measured, 12.0, 200, 1);
  EXPECT_LT(wide.median_p, 0.05);
  // Reproducible from its seed, and the seed matters.
  const auto again = stats::ks_with_measurement_noise(model, measured, 3.0, 200, 1);
  EXPECT_EQ(again.median_p, right.median_p);
  EXPECT_EQ(again.share_p_above_005, right.share_p_above_005);
  const auto other = stats::ks_with_measurement_noise(model, measured, 3.0, 200, 2);
  EXPECT_NE(other.median_p, right.median_p);
}

TEST(KolmogorovSmirnovWithNoise, RefusesBadArguments) {
  const std::vector<double> a = {1, 2, 3}, b = {1, 2, 4};
  EXPECT_THROW(stats::ks_with_measurement_noise(a, b, -0.1, 10, 1), std::invalid_argument);
  EXPECT_THROW(stats::ks_with_measurement_noise(a, b, kNaN, 10, 1), std::invalid_argument);
  EXPECT_THROW(stats::ks_with_measurement_noise(a, b, 0.1, 0, 1), std::invalid_argument);
  EXPECT_THROW(stats::ks_with_measurement_noise(std::vector<double>{}, b, 0.1, 10, 1),
               std::invalid_argument);
}

TEST(Pearson, FourPairsMatchStudentWithTwoDegreesOfFreedom) {
  // n = 4: t = r sqrt(2 / (1 - r^2)) has 2 degrees of freedom, whose CDF is closed-form:
  // P(|T| > |t|) = 1 - |t| / sqrt(2 + t^2) = 1 - |r|.
  const std::vector<double> x = {1, 2, 3, 4};
  const std::vector<double> y = {2, 1, 4, 3};
  const auto c = stats::pearson(x, y);
  EXPECT_EQ(c.n, 4u);
  EXPECT_NEAR(c.r, 0.6, 1e-12);
  EXPECT_NEAR(c.p_value, 0.4, 1e-9);
  const std::vector<double> yneg = {3, 4, 1, 2};
  const auto cn = stats::pearson(x, yneg);
  EXPECT_NEAR(cn.r, -0.6, 1e-12);
  EXPECT_NEAR(cn.p_value, 0.4, 1e-9);  // two-sided
}

TEST(Pearson, ThreePairsMatchCauchy) {
  // n = 3: one degree of freedom (Cauchy), P(|T| > |t|) = 1 - (2 / pi) atan(|t|).
  const std::vector<double> x = {0, 1, 2};
  const std::vector<double> y = {0, 2, 1};
  const auto c = stats::pearson(x, y);
  const double r = 0.5;  // sxy = 1, sxx = 2, syy = 2
  EXPECT_NEAR(c.r, r, 1e-12);
  const double t = r * std::sqrt(1.0 / (1.0 - r * r));
  EXPECT_NEAR(c.p_value, 1.0 - 2.0 / std::numbers::pi * std::atan(t), 1e-9);
}

TEST(Pearson, NanPairsSkippedDegenerateCasesAreNan) {
  const std::vector<double> x = {1, 2, kNaN, 3, 4};
  const std::vector<double> y = {2, 1, 7, 4, 3};
  const auto c = stats::pearson(x, y);
  EXPECT_EQ(c.n, 4u);
  EXPECT_NEAR(c.r, 0.6, 1e-12);
  const auto constant = stats::pearson(std::vector<double>{1, 2, 3}, std::vector<double>{5, 5, 5});
  EXPECT_TRUE(std::isnan(constant.r));
  const auto two = stats::pearson(std::vector<double>{1, 2}, std::vector<double>{1, 2});
  EXPECT_TRUE(std::isnan(two.p_value));
  EXPECT_THROW(stats::pearson(std::vector<double>{1, 2}, std::vector<double>{1}),
               std::invalid_argument);
}

TEST(Pearson, LabCorrelationAgainstStudentTables) {
  // Triangles: V_in^x against V_out^x (the slope behind A_xx in paper Table 3).
  const ImpactSet tri = read_impact_set(kLab + "triangles.csv");
  const auto x = tri.feature("vin_x");
  const auto y = tri.feature("vout_x");
  const auto c = stats::pearson(x, y);
  EXPECT_EQ(c.n, 31u);
  const auto sx = stats::summarize(x);
  const auto sy = stats::summarize(y);
  double sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sxy += (x[i] - sx.mean) * (y[i] - sy.mean);
  EXPECT_NEAR(c.r, sxy / (30.0 * sx.std * sy.std), 1e-12);
  // t = r sqrt(29 / (1 - r^2)) lies between the two-sided 1 % and 0.1 % critical values of
  // Student's t with 29 degrees of freedom (2.756 and 3.659), so 0.001 < p < 0.01.
  const double t = c.r * std::sqrt(29.0 / (1.0 - c.r * c.r));
  ASSERT_GT(t, 2.756);
  ASSERT_LT(t, 3.659);
  EXPECT_GT(c.p_value, 0.001);
  EXPECT_LT(c.p_value, 0.01);
}

}  // namespace
}  // namespace ricochet

// The O(n log n) statistic and the p-value agree with OpenTURNS's own two-sample test,
// including with ties (the lab data are rounded to 0.01).
TEST(Stats, KsMatchesOpenTurnsTwoSampleTest) {
  const auto cyl =
      ricochet::read_impact_set(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
  const auto tri =
      ricochet::read_impact_set(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/triangles.csv");
  for (const char* f : {"vin_x", "vout_x", "vout_y", "wout"}) {
    const auto a = cyl.feature(f), b = tri.feature(f);
    OT::Sample sa(a.size(), 1), sb(b.size(), 1);
    for (std::size_t i = 0; i < a.size(); ++i) sa(i, 0) = a[i];
    for (std::size_t i = 0; i < b.size(); ++i) sb(i, 0) = b[i];
    const OT::TestResult ot = OT::HypothesisTest::TwoSamplesKolmogorov(sa, sb);
    const auto ours = ricochet::stats::ks_two_sample(a, b);
    EXPECT_NEAR(ours.statistic, ot.getStatistic(), 1e-12) << f;
    EXPECT_NEAR(ours.p_value, ot.getPValue(), 1e-12) << f;
  }
}

namespace ricochet::stats {
namespace {

// Holm (1979): p = (0.01, 0.04, 0.03, 0.005) -> sorted 0.005, 0.01, 0.03, 0.04 times 4, 3, 2, 1
// = 0.02, 0.03, 0.06, 0.04 -> monotone 0.02, 0.03, 0.06, 0.06 (by hand).
TEST(Multiplicity, HolmAdjustmentByHand) {
  const std::vector<double> p{0.01, 0.04, 0.03, 0.005};
  const auto a = holm_adjust(p);
  EXPECT_NEAR(a[3], 0.02, 1e-15);
  EXPECT_NEAR(a[0], 0.03, 1e-15);
  EXPECT_NEAR(a[2], 0.06, 1e-15);
  EXPECT_NEAR(a[1], 0.06, 1e-15);
  // Untested members of the family (screened out) count: m = 10.
  const auto b = holm_adjust(std::vector<double>{0.004}, 10);
  EXPECT_NEAR(b[0], 0.04, 1e-15);
  EXPECT_TRUE(std::isnan(holm_adjust(std::vector<double>{NAN, 0.01})[0]));
}

// A published interval of k successes out of n, to the 4 decimals printed.
struct PublishedInterval {
  std::size_t k, n;
  double lo, hi;
};

void expect_published(Proportion (*interval)(std::size_t, std::size_t, double),
                      std::span<const PublishedInterval> table) {
  for (const auto& p : table) {
    const Proportion got = interval(p.k, p.n, 0.05);
    EXPECT_NEAR(got.lo, p.lo, 5e-4) << p.k << "/" << p.n;
    EXPECT_NEAR(got.hi, p.hi, 5e-4) << p.k << "/" << p.n;
  }
}

// Wilson (1927): 9 of 10 at 95 %: [0.5958, 0.9821] (e.g. Newcombe 1998, Stat. Med. 17:857,
// Table I, method 3, for 81/263 reproduced below too).
TEST(Multiplicity, WilsonIntervalsMatchNewcombe) {
  constexpr PublishedInterval kNewcombe[] = {
      {9, 10, 0.5958, 0.9821}, {81, 263, 0.2553, 0.3662}, {0, 40, 0.0, 0.0876}};
  expect_published(wilson, kNewcombe);
  EXPECT_NEAR(wilson(0, 40).lo, 0.0, 1e-15);
}

// Newcombe (1998, Stat. Med. 17:857), Table I, method 5 ("exact"): the Clopper-Pearson limits of
// his examples; at k = 0 and k = n they are closed forms, 1 - (alpha/2)^(1/n) and its mirror.
TEST(Multiplicity, ClopperPearsonIntervalsMatchNewcombe) {
  constexpr PublishedInterval kNewcombe[] = {
      {81, 263, 0.2527, 0.3676}, {15, 148, 0.0578, 0.1617}, {1, 29, 0.0009, 0.1776}};
  expect_published(clopper_pearson, kNewcombe);
  const Proportion z = clopper_pearson(0, 20);
  EXPECT_EQ(z.lo, 0.0);
  EXPECT_NEAR(z.hi, 1.0 - std::pow(0.025, 1.0 / 20.0), 1e-9);
  const Proportion all = clopper_pearson(20, 20);
  EXPECT_EQ(all.hi, 1.0);
  EXPECT_NEAR(all.lo, std::pow(0.025, 1.0 / 20.0), 1e-9);
  const Proportion a = clopper_pearson(81, 263);
  // Wider than Wilson's: its coverage is at least nominal.
  const Proportion w = wilson(81, 263);
  EXPECT_LT(a.lo, w.lo);
  EXPECT_GT(a.hi, w.hi);
}

// Nadeau & Bengio (2003): the variance of the mean of J split differences is inflated by
// n_test/n_train; by hand for d = (1, 2, 3, 4): mean 2.5, s^2 = 5/3, J = 4, n_test/n_train =
// 1/4: se = sqrt((1/4 + 1/4) 5/3) = 0.9129, t = 2.7386, one-sided p of Student(3) = 0.0357.
TEST(Multiplicity, CorrectedResampledTTestByHand) {
  const std::vector<double> d{1, 2, 3, 4};
  const ResampledTest t = corrected_resampled_t(d, 10, 40);
  EXPECT_NEAR(t.mean, 2.5, 1e-12);
  EXPECT_NEAR(t.se, 0.912871, 1e-6);
  EXPECT_NEAR(t.t, 2.738613, 1e-6);
  EXPECT_NEAR(t.p_value, 0.03569, 2e-4);
  EXPECT_NEAR(student_t_upper_tail(0.0, 5.0), 0.5, 1e-12);
  EXPECT_NEAR(chi_square_upper_tail(3.841459, 1.0), 0.05, 1e-6);
}

}  // namespace
}  // namespace ricochet::stats
