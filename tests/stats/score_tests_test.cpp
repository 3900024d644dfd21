// The robust score tests and their step-down max-T adjustment (stats/score_tests.hpp), checked
// against distributions known in closed form, not against the code's own output.
#include "stats/score_tests.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "stats/stats.hpp"

namespace ricochet::stats {
namespace {

// Per-unit contributions u_i = g_i e_i with fixed g and Gaussian e: the score of a linear model.
std::vector<double> contributions(std::size_t n, std::mt19937_64& rng, double shift = 0) {
  std::normal_distribution<double> normal;
  std::vector<double> u(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double g = 0.5 + static_cast<double>(i % 7) / 7.0;
    u[i] = g * (normal(rng) + shift);
  }
  return u;
}

// One column: the bootstrap p is the Student-t tail with n - q - 1 degrees of freedom (the
// multivariate t of one column is Student's t) of the observed statistic.
TEST(ScoreTests, OneColumnGivesStudentTTail) {
  std::mt19937_64 rng(3);
  for (double shift : {0.2, 0.35, 0.5}) {
    const std::vector<ScoreColumn> cols{{0, contributions(40, rng, shift), false}};
    const ScoreTests r = robust_score_tests(cols, 1, {.nuisance = 3});
    EXPECT_EQ(r.dof, 36.0);
    const double exact = student_t_upper_tail(r.statistic[0], r.dof);
    // Monte Carlo error of 20,000 draws: sd sqrt(p (1 - p) / 20000) <= 0.0035.
    EXPECT_NEAR(r.p_value[0], exact, 0.012) << "T = " << r.statistic[0];
    EXPECT_DOUBLE_EQ(r.p_adjusted[0], r.p_value[0]);
  }
  // Two-sided: twice the tail of |T|.
  const std::vector<ScoreColumn> two{{0, contributions(40, rng, -0.4), true}};
  const ScoreTests r = robust_score_tests(two, 1, {.nuisance = 3});
  EXPECT_NEAR(r.p_value[0], 2 * student_t_upper_tail(r.statistic[0], r.dof), 0.012);
  EXPECT_LT(r.t[0], 0);
}

// Identical hypotheses are one test: the max-T adjustment costs nothing, where Holm multiplies
// by their number.
TEST(ScoreTests, IdenticalHypothesesCostNothing) {
  std::mt19937_64 rng(5);
  const std::vector<double> u = contributions(40, rng, 0.8);
  std::vector<ScoreColumn> cols;
  for (std::size_t h = 0; h < 10; ++h) cols.push_back({h, u, false});
  const ScoreTests r = robust_score_tests(cols, 10, {.nuisance = 2});
  for (std::size_t h = 0; h < 10; ++h) EXPECT_NEAR(r.p_adjusted[h], r.p_value[h], 1e-12);
  EXPECT_LT(r.p_value[0], 0.01);
  const std::vector<double> holm = holm_adjust(r.p_value);
  EXPECT_GT(holm[0], 5 * r.p_adjusted[0]);
}

// Multiple comparisons with the best (ScoreTests::mcb_critical): twins cost nothing against each
// other (their deficit draws are 0, so c is the reference's comparison alone), a strong
// hypothesis leaves a null one and the reference out of the set, and the set covers the
// hypothesis of largest expected statistic at the MCB level over many data sets.
TEST(ScoreTests, MultipleComparisonsWithTheBest) {
  std::mt19937_64 rng(11);
  const std::vector<double> strong = contributions(40, rng, 0.9);
  const std::vector<double> null = contributions(40, rng, 0.0);
  const std::vector<ScoreColumn> cols{{0, strong, false}, {1, strong, false}, {2, null, false}};
  const ScoreTests r = robust_score_tests(cols, 3, {.nuisance = 2, .mcb_level = 0.05});
  ASSERT_EQ(r.mcb_critical.size(), 3u);
  auto in_set = [&](std::size_t h) {
    double other = 0;
    for (std::size_t k = 0; k < 3; ++k)
      if (k != h) other = std::max(other, r.statistic[k]);
    return r.statistic[h] >= other - r.mcb_critical[h];
  };
  EXPECT_TRUE(in_set(0));
  EXPECT_TRUE(in_set(1));
  EXPECT_FALSE(in_set(2)) << "T " << r.statistic[2] << " vs " << r.statistic[0];
  // The reference (nothing added) is out: the best statistic exceeds its critical value, which
  // is the single-step max-T value.
  EXPECT_GT(r.statistic[0], r.mcb_reference_critical);
  EXPECT_NEAR(r.mcb_reference_critical, max_null_quantile(r, 0.05), 1e-12);

  // Coverage: hypothesis 0 has the largest expected statistic (shift 0.3 against 0.2 and 0);
  // over 200 data sets it is in the set at least 95 % of the time (Monte Carlo: 2 sd of a 0.95
  // rate over 200 is 0.03).
  int covered = 0;
  for (int rep = 0; rep < 200; ++rep) {
    std::mt19937_64 g(1000 + rep);
    std::normal_distribution<double> normal;
    std::vector<double> e(40);
    for (double& x : e) x = normal(g);
    // Three hypotheses on the same units (correlated), shifts 0.3, 0.2, 0.
    std::vector<ScoreColumn> c;
    for (std::size_t h = 0; h < 3; ++h) {
      std::vector<double> u(40);
      for (std::size_t i = 0; i < 40; ++i) {
        const double own = normal(g);
        u[i] = 0.7 * e[i] + 0.7 * own + (h == 0 ? 0.3 : h == 1 ? 0.2 : 0.0);
      }
      c.push_back({h, u, false});
    }
    const ScoreTests t = robust_score_tests(
        c, 3,
        {.nuisance = 0, .mcb_level = 0.05, .draws = 2000, .seed = static_cast<std::uint64_t>(rep)});
    const double other = std::max({0.0, t.statistic[1], t.statistic[2]});
    covered += t.statistic[0] >= other - t.mcb_critical[0] ? 1 : 0;
  }
  EXPECT_GE(covered, 184);
}

// Independent hypotheses (columns on disjoint units; many units so that the shared chi-square
// factor is 1): the smallest p is adjusted by Sidak, 1 - (1 - p)^m.
TEST(ScoreTests, IndependentHypothesesGiveSidak) {
  std::mt19937_64 rng(11);
  const std::size_t m = 5, per = 400, n = m * per;
  std::vector<ScoreColumn> cols;
  for (std::size_t h = 0; h < m; ++h) {
    std::vector<double> u(n, 0.0);
    const std::vector<double> part = contributions(per, rng, h == 0 ? 0.11 : 0.0);
    std::copy(part.begin(), part.end(), u.begin() + static_cast<std::ptrdiff_t>(h * per));
    cols.push_back({h, u, false});
  }
  const ScoreTests r = robust_score_tests(cols, m, {.nuisance = 0, .draws = 40000});
  std::size_t best = 0;
  for (std::size_t h = 1; h < m; ++h)
    if (r.statistic[h] > r.statistic[best]) best = h;
  const double p = 1 - std::erf(r.statistic[best] / std::sqrt(2.0)) / 2 - 0.5;  // normal tail
  EXPECT_NEAR(r.p_value[best], p, 0.006);
  EXPECT_NEAR(r.p_adjusted[best], 1 - std::pow(1 - p, static_cast<double>(m)), 0.012);
}

// Size and power: under H0 (10 correlated hypotheses, 40 units) the family-wise rejection rate
// at 0.05 is at most 0.05 (its Wilson interval reaches below 0.05); with one real effect of
// noncentrality about 4 (0.85 sqrt(40 mean g^2)), which a lone two-sided test at 0.05 finds 98 %
// of the time and a Bonferroni test over the 10 about 80 %, the family finds it most times.
TEST(ScoreTests, ControlsTheFamilyWiseErrorAndKeepsPower) {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> normal;
  const std::size_t reps = 300, n = 40, m = 10;
  std::size_t false_alarms = 0, found = 0;
  for (std::size_t rep = 0; rep < reps; ++rep) {
    for (int alt = 0; alt < 2; ++alt) {
      std::vector<double> e(n);
      for (double& x : e) x = normal(rng);
      std::vector<ScoreColumn> cols;
      for (std::size_t h = 0; h < m; ++h) {
        std::vector<double> u(n);
        for (std::size_t i = 0; i < n; ++i) {
          // Directions correlated in pairs (h and h + 1 share a component).
          const double g = std::sin(0.3 * static_cast<double>(i) * static_cast<double>(h / 2 + 1)) +
                           0.3 * static_cast<double>(h % 2);
          const double effect = alt == 1 && h == 3 ? 0.85 * g : 0.0;
          u[i] = g * (e[i] + effect);
        }
        cols.push_back({h, std::move(u), h % 3 == 0});
      }
      const ScoreTests r = robust_score_tests(cols, m, {.nuisance = 3, .draws = 2000});
      bool any = false;
      for (double p : r.p_adjusted) any = any || p < 0.05;
      if (alt == 0) false_alarms += any;
      if (alt == 1) found += r.p_adjusted[3] < 0.05;
    }
  }
  const Proportion fa = wilson(false_alarms, reps);
  EXPECT_LE(fa.lo, 0.05) << false_alarms << "/" << reps;
  EXPECT_GT(fa.hi, 0.01) << "far too conservative: " << false_alarms << "/" << reps;
  EXPECT_GT(wilson(found, reps).lo, 0.5) << found << "/" << reps;
}

TEST(ScoreTests, RejectsMalformedColumns) {
  const std::vector<ScoreColumn> unequal{{0, {1, 2, 3, 4}, false}, {1, {1, 2, 3}, false}};
  EXPECT_THROW(robust_score_tests(unequal, 2), std::invalid_argument);
  const std::vector<ScoreColumn> out_of_range{{2, {1, 2, 3, 4}, false}};
  EXPECT_THROW(robust_score_tests(out_of_range, 2), std::invalid_argument);
  const std::vector<ScoreColumn> few{{0, {1, 2, 3}, false}};
  EXPECT_THROW(robust_score_tests(few, 1, {.nuisance = 2}), std::invalid_argument);
  // A column of zeros cannot be tested: p = 1, it enters no maximum.
  // (The other column, by hand: mean 1.4, centred sum of squares 2.4, 9 degrees of freedom:
  // T = 14 / sqrt(10 x 2.4 / 9) = 8.573, p = 6e-6.)
  const std::vector<ScoreColumn> zero{{0, std::vector<double>(10, 0.0), false},
                                      {1, {1, 2, 1, 2, 1, 1, 2, 1, 2, 1}, false}};
  const ScoreTests r = robust_score_tests(zero, 2);
  EXPECT_EQ(r.p_value[0], 1.0);
  EXPECT_EQ(r.p_adjusted[0], 1.0);
  EXPECT_NEAR(r.t[1], 14.0 / std::sqrt(10 * 2.4 / 9), 1e-12);
  EXPECT_LT(r.p_value[1], 2e-4);  // no draw of 20,000 reaches it: p = 1 / 20001
}

}  // namespace
}  // namespace ricochet::stats
