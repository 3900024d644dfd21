// Robust summaries, the gross-error rule and the response test, each checked against a hand
// computation or against its sampling distribution over many seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "impact/impact_set.hpp"
#include "stats/robust.hpp"

namespace ricochet {
namespace {

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

TEST(RobustSummary, MedianAndScaledMadByHand) {
  // median 3; |x - 3| = 2, 1, 0, 1, 97: MAD 1.
  const std::vector<double> x = {1, 2, 3, 4, 100};
  const auto s = stats::robust_summarize(x);
  EXPECT_EQ(s.n, 5u);
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_DOUBLE_EQ(s.mad_sd, 1.4826);
  // Even count: the mean of the two middle values; NaN skipped.
  const std::vector<double> y = {4, 1, std::nan(""), 3, 2};
  EXPECT_DOUBLE_EQ(stats::robust_summarize(y).median, 2.5);
}

TEST(RobustSummary, MadScaleEstimatesTheNormalSd) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(5.0, 2.0);
  std::vector<double> x(200000);
  for (double& v : x) v = n(rng);
  const auto s = stats::robust_summarize(x);
  // Standard error of the MAD scale for n = 2e5: about 1.17 * 2 / sqrt(n) ~ 0.005.
  EXPECT_NEAR(s.mad_sd, 2.0, 0.02);
  EXPECT_NEAR(s.median, 5.0, 0.02);
}

TEST(GrossErrors, ModifiedZByHand) {
  // median 3, MAD 1: M = 0.6745 (x - 3).
  const std::vector<double> x = {1, 2, 3, 4, 100};
  const auto z = stats::modified_z_scores(x);
  EXPECT_DOUBLE_EQ(z[0], -2 * 0.6745);
  EXPECT_DOUBLE_EQ(z[4], 97 * 0.6745);
  const std::vector<std::vector<double>> cols = {x, {0, 0, 1, 0, 0}};
  const std::vector<std::string> names = {"a", "b"};
  const auto g = stats::flag_gross_errors(cols, names);
  // Column b has MAD 0: no scores, no flags from it.
  EXPECT_EQ(g.count, 1u);
  EXPECT_TRUE(g.flagged[4]);
  EXPECT_NE(g.why[4].find("a (M = +65.4)"), std::string::npos) << g.why[4];
  EXPECT_THROW(stats::flag_gross_errors(cols, std::vector<std::string>{"a"}),
               std::invalid_argument);
}

TEST(GrossErrors, RareOnCleanNormalSamples) {
  // Under normality |M| > 3.5 has probability about 2 * Phi(-3.5 / 0.6745 * 0.6745) = 4.7e-4 per
  // value (M is close to a standard normal for large n). Over 2,000 samples of 28 values, the
  // expected number of flagged values is about 26; allow the Poisson 99.9 % band.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  std::size_t flagged = 0, total = 0;
  for (int rep = 0; rep < 2000; ++rep) {
    std::vector<double> x(28);
    for (double& v : x) v = n(rng);
    const std::vector<std::vector<double>> cols = {x};
    const std::vector<std::string> names = {"x"};
    flagged += stats::flag_gross_errors(cols, names).count;
    total += x.size();
  }
  const double rate = static_cast<double>(flagged) / static_cast<double>(total);
  // Small samples have a noisier MAD, so the rate is above the asymptotic 4.7e-4; it stays far
  // below the 5 of 28 (18 %) that the lab cylinders show.
  EXPECT_LT(rate, 5e-3) << flagged << " of " << total;
}

TEST(GrossErrors, TheLabCylindersHoldSixFlaggedReleases) {
  // The rule on the lab's six velocities alone (no model): C07, C08, C12, C13, C15 and C24, by hand
  // from Appendix A (e.g. C24's omega_out -77.82 rad/s against the median -40.2, MAD 2.27).
  const ImpactSet lab = read_impact_set(kLab + "cylinders.csv");
  std::vector<std::vector<double>> cols;
  std::vector<std::string> names;
  for (const char* c : {"vin_x", "vin_y", "win", "vout_x", "vout_y", "wout"}) {
    cols.push_back(lab.feature(c));
    names.emplace_back(c);
  }
  const auto g = stats::flag_gross_errors(cols, names);
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < g.flagged.size(); ++i)
    if (g.flagged[i]) ids.push_back(lab.impacts[i].id);
  // C15's omega_out (-52.55) is at M = -3.7 as well.
  EXPECT_EQ(ids, (std::vector<std::string>{"C07", "C08", "C12", "C13", "C15", "C24"}));
}

TEST(ResponseCheck, DetectsAnUnresponsiveMeasurement) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  // 100 pairs: the measured slope's standard error is about 0.1 against a model slope of 0.9.
  std::vector<double> in(100), model_out(100), meas_out(100);
  for (std::size_t i = 0; i < in.size(); ++i) {
    in[i] = n(rng);
    model_out[i] = 0.9 * in[i] + 0.2 * n(rng);  // r about 0.98
    meas_out[i] = n(rng);                       // r about 0
  }
  const auto r = stats::compare_responses(in, model_out, in, meas_out);
  EXPECT_GT(r.r_model, 0.9);
  EXPECT_LT(std::abs(r.r_measured), 0.5);
  EXPECT_LT(r.p_value, 1e-6);
  EXPECT_NEAR(r.slope_model, 0.9, 0.1);
  EXPECT_NEAR(r.reliability, 0.0, 0.3);
  EXPECT_EQ(r.n_model, 100u);
}

TEST(ResponseCheck, FalsePositiveRateIsNominal) {
  // Model and measurements with the same true correlation 0.6: the test must reject at about
  // its level. 2,000 repetitions: the 5 % rate's 99.9 % binomial band is about [3.4 %, 6.8 %].
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  int rejected = 0;
  const int reps = 2000;
  for (int rep = 0; rep < reps; ++rep) {
    std::vector<double> a(28), b(28), c(28), d(28);
    for (std::size_t i = 0; i < a.size(); ++i) {
      a[i] = n(rng);
      b[i] = 0.6 * a[i] + 0.8 * n(rng);
      c[i] = n(rng);
      d[i] = 0.6 * c[i] + 0.8 * n(rng);
    }
    rejected += stats::compare_responses(a, b, c, d).p_value < 0.05 ? 1 : 0;
  }
  const double rate = static_cast<double>(rejected) / reps;
  EXPECT_GT(rate, 0.034);
  EXPECT_LT(rate, 0.068);
}

TEST(ResponseCheck, TooFewPairsGiveNaN) {
  const std::vector<double> x = {1, 2, 3}, y = {1, 2, 4};
  const auto r = stats::compare_responses(x, y, x, y);
  EXPECT_TRUE(std::isnan(r.p_value));
}

}  // namespace
}  // namespace ricochet
