// The orientation rules of releases whose orientation is unknown (fit/orientation_rule.hpp,
// issue 35): the per-release shift, the rule's points, its unbiasedness over shifts and its
// quadrature error estimate, on an integrand with the features of the triangles' (jumps where
// the contact sequence switches, a smooth part), whose exact mean is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <string>

#include "fit/fit.hpp"
#include "fit/orientation_rule.hpp"

namespace ricochet::fit {
namespace {

TEST(OrientationRule, TheShiftIsAFixedFractionOfACellPerReleaseId) {
  EXPECT_EQ(release_rotation("T01"), release_rotation("T01"));
  std::set<double> seen;
  for (int i = 0; i < 200; ++i) {
    const double r = release_rotation("T" + std::to_string(i));
    EXPECT_GE(r, 0.0);
    EXPECT_LT(r, 1.0);
    seen.insert(r);
  }
  EXPECT_EQ(seen.size(), 200u);
  // FNV-1a of the empty string is the offset basis 0xcbf29ce484222325.
  EXPECT_DOUBLE_EQ(release_rotation(""),
                   static_cast<double>(0xcbf29ce484222325ull >> 11) * 0x1.0p-53);
}

TEST(OrientationRule, PointsAreOnePerCellAtTheShift) {
  AlphaOptions a;
  a.min_rad = -1.0;
  a.max_rad = 2.0;
  const auto g = orientation_rule(a, 6, 0.25);
  ASSERT_EQ(g.size(), 6u);
  for (std::size_t k = 0; k < g.size(); ++k)
    EXPECT_NEAR(g[k], -1.0 + 3.0 * (static_cast<double>(k) + 0.25) / 6.0, 1e-15);
  const auto mid = orientation_rule(a, 4, 0.5);
  EXPECT_NEAR(mid.front(), -1.0 + 3.0 / 8.0, 1e-15);
}

TEST(OrientationRule, HalvesAreTheInterleavedRules) {
  const RuleMean m = rule_mean({1.0, 3.0, 2.0, 6.0});
  EXPECT_DOUBLE_EQ(m.mean, 3.0);
  EXPECT_DOUBLE_EQ(m.half[0], 1.5);
  EXPECT_DOUBLE_EQ(m.half[1], 4.5);
  EXPECT_DOUBLE_EQ(m.error(), 1.5);
  EXPECT_DOUBLE_EQ(m.mean_sq, (1.0 + 9.0 + 4.0 + 36.0) / 4.0);
  const RuleMean odd = rule_mean({1.0, 2.0, 6.0});
  EXPECT_DOUBLE_EQ(odd.error(), 0.0);
}

// Two jumps (contact-sequence switches) and a smooth periodic part over the unit window.
double integrand(double x) {
  return (x > 0.37 ? 1.0 : 0.0) + (x > 0.81 ? 0.5 : 0.0) + 0.3 * std::sin(2.0 * M_PI * x);
}
constexpr double kExact = (1.0 - 0.37) + 0.5 * (1.0 - 0.81);

struct Rms {
  double error = 0, estimate = 0, bias = 0, bias_se = 0;
};
Rms over_shifts(int n, int trials, unsigned seed) {
  AlphaOptions a;
  a.min_rad = 0.0;
  a.max_rad = 1.0;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double se = 0, ss = 0, sum = 0;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> v;
    for (double x : orientation_rule(a, n, u(rng))) v.push_back(integrand(x));
    const RuleMean m = rule_mean(v);
    const double e = m.mean - kExact;
    sum += e;
    se += e * e;
    ss += m.error() * m.error();
  }
  Rms r;
  r.error = std::sqrt(se / trials);
  r.estimate = std::sqrt(ss / trials);
  r.bias = sum / trials;
  r.bias_se = r.error / std::sqrt(static_cast<double>(trials));
  return r;
}

// A randomly shifted rule is unbiased (its mean over shifts is the integral), its error falls
// about as 1/n on an integrand with jumps, and the half-rule estimate has the error's size (an
// estimate, not a bound: here its rms is 1.1-2.6 x the actual rms error).
TEST(OrientationRule, ShiftedRulesAreUnbiasedAndTheEstimateTracksTheError) {
  const Rms r12 = over_shifts(12, 4000, 7), r24 = over_shifts(24, 4000, 8),
            r48 = over_shifts(48, 4000, 9);
  for (const Rms& r : {r12, r24, r48}) {
    EXPECT_LT(std::fabs(r.bias), 3.0 * r.bias_se) << r.bias;
    EXPECT_GT(r.estimate, 0.7 * r.error);
    EXPECT_LT(r.estimate, 4.0 * r.error);
  }
  EXPECT_LT(r48.error, 0.5 * r12.error);
}

}  // namespace
}  // namespace ricochet::fit
