// Sparse regression over groups (stats/sparse_regression.hpp): a subset fit's exact recovery,
// the leak-free held-out prediction, recovery of a sparse law through collinear terms, group
// scatter and noise, and no discovery in noise.
#include "stats/sparse_regression.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>

#include "common/error.hpp"

namespace ricochet::stats {
namespace {

// Eight terms of two contact-like variables per sample, u in (0, 1) (a penetration) and v (a
// speed): u, u^1.5, u^2, v, v|v|, u v^2, u v, u [v > 0] (a loading-branch switch). u, u^1.5 and
// u^2 are strongly collinear, as the penetration powers of a contact are.
constexpr std::size_t kTerms = 8;
struct Data {
  std::vector<double> x, y;
  std::vector<std::size_t> group;
  SparseDesign design() const { return {x, kTerms, y, group}; }
};

void add_sample(Data& d, double u, double v, std::size_t g, double y) {
  const double row[kTerms] = {u,     std::pow(u, 1.5), u * u, v, v * std::abs(v), u * v * v,
                              u * v, v > 0 ? u : 0.0};
  d.x.insert(d.x.end(), row, row + kTerms);
  d.y.push_back(y);
  d.group.push_back(g);
}

// `groups` releases of `samples` each along a contact-like path (u rises and falls, v changes
// sign at the deepest point). The response: a * u^1.5 + b * v|v|, each coefficient scattered
// from group to group by `scatter` (relative sd), plus noise of sd `noise`.
Data contact_data(std::uint64_t seed, double a, double b, double scatter, double noise,
                  std::size_t groups = 30, std::size_t samples = 40) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0, 1);
  std::uniform_real_distribution<double> speed(0.5, 2.0);
  Data d;
  for (std::size_t g = 0; g < groups; ++g) {
    const double v0 = speed(rng);
    const double ag = a * (1 + scatter * n01(rng)), bg = b * (1 + scatter * n01(rng));
    for (std::size_t k = 0; k < samples; ++k) {
      const double s = M_PI * (static_cast<double>(k) + 0.5) / static_cast<double>(samples);
      const double u = 0.5 * v0 * std::sin(s), v = v0 * std::cos(s);
      add_sample(d, u, v, g, ag * std::pow(u, 1.5) + bg * v * std::abs(v) + noise * n01(rng));
    }
  }
  return d;
}

TEST(SparseRegression, ASubsetFitRecoversANoiselessLawExactly) {
  const Data d = contact_data(1, 2.0, -0.5, 0.0, 0.0);
  const std::vector<double> c = subset_fit(d.design(), (1u << 1) | (1u << 4));
  for (std::size_t j = 0; j < kTerms; ++j) {
    const double truth = j == 1 ? 2.0 : j == 4 ? -0.5 : 0.0;
    EXPECT_NEAR(c[j], truth, 1e-9) << "term " << j;
  }
  // All eight terms: the law is in their span, so least squares finds it too.
  const std::vector<double> all = subset_fit(d.design(), (1u << kTerms) - 1);
  double worst = 0;
  for (std::size_t i = 0; i < d.y.size(); ++i) {
    double p = 0;
    for (std::size_t j = 0; j < kTerms; ++j) p += d.x[i * kTerms + j] * all[j];
    worst = std::max(worst, std::abs(p - d.y[i]));
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(SparseRegression, AHeldOutPredictionIgnoresItsOwnGroupsResponse) {
  Data d = contact_data(2, 2.0, -0.5, 0.1, 0.05, 12);
  const std::vector<std::size_t> fold = {0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2};
  const std::vector<double> before =
      heldout_predictions(d.design(), (1u << 1) | (1u << 4) | (1u << 2), fold);
  for (std::size_t i = 0; i < d.y.size(); ++i)
    if (d.group[i] == 4) d.y[i] = 100.0 + 50.0 * std::sin(static_cast<double>(i));
  const std::vector<double> after =
      heldout_predictions(d.design(), (1u << 1) | (1u << 4) | (1u << 2), fold);
  std::size_t changed_elsewhere = 0;
  for (std::size_t i = 0; i < d.y.size(); ++i) {
    if (d.group[i] == 4)
      EXPECT_EQ(before[i], after[i]) << "sample " << i << " saw its own group";
    else
      changed_elsewhere += before[i] != after[i];
  }
  EXPECT_GT(changed_elsewhere, 0u) << "group 4 trains the other folds' fits";
}

// Recovery over fixed seeds: the law's two terms among eight, three of them collinear
// powers of u, with 10 % group-to-group scatter of both coefficients and noise. Counted, not
// required seed by seed. SPARSE_DEBUG=1 runs seeds 101-160 and prints each fit; the rates
// measured there are in docs/diagnosis.md ("The force-residual discovery"). Where the support
// wavers between the collinear powers, the interval falls short of its level (post-selection
// inference, Berk et al. 2013, Ann. Stat. 41:802).
TEST(SparseRegression, FindsTheTrueTermsThroughCollinearityScatterAndNoise) {
  std::size_t exact = 0, covered_a = 0, covered_b = 0;
  for (std::uint64_t seed = 101; seed <= (std::getenv("SPARSE_DEBUG") ? 160 : 110); ++seed) {
    const Data d = contact_data(seed, 2.0, -0.5, 0.10, 0.02);
    SparseOptions o;
    o.seed = seed;
    const SparseResult r = sparse_regression(d.design(), o);
    bool ok = true;
    for (std::size_t j = 0; j < kTerms; ++j) ok = ok && r.active[j] == (j == 1 || j == 4);
    exact += ok;
    covered_a += r.lo[1] <= 2.0 && 2.0 <= r.hi[1];
    covered_b += r.lo[4] <= -0.5 && -0.5 <= r.hi[4];
    std::string line = "seed " + std::to_string(seed) + " size " + std::to_string(r.size) + ":";
    for (std::size_t j = 0; j < kTerms; ++j)
      line += " " + std::to_string(r.coef[j]) + " [" + std::to_string(r.lo[j]) + ", " +
              std::to_string(r.hi[j]) + "] in " + std::to_string(r.inclusion[j]) + ";";
    RecordProperty("seed" + std::to_string(seed), line);
    if (std::getenv("SPARSE_DEBUG")) printf("%s\n", line.c_str());
    EXPECT_LT(r.cv_error[2], r.cv_error[0]) << seed;
  }
  EXPECT_GE(exact, 9u);
  EXPECT_GE(covered_a, 7u);
  EXPECT_GE(covered_b, 8u);
}

// Noise only (with the same group structure): the empty model must be chosen in most seeds.
TEST(SparseRegression, FindsNothingInNoise) {
  std::size_t empty = 0;
  for (std::uint64_t seed = 201; seed <= 220; ++seed) {
    const Data d = contact_data(seed, 0.0, 0.0, 0.0, 0.05);
    SparseOptions o;
    o.seed = seed;
    o.bootstrap = 0;
    const SparseResult r = sparse_regression(d.design(), o);
    empty += r.size == 0;
  }
  if (std::getenv("SPARSE_DEBUG")) printf("empty model in %zu of 20 noise sets\n", empty);
  EXPECT_GE(empty, 17u) << "false discoveries in " << 20 - empty << " of 20 noise sets";
}

TEST(SparseRegression, SameSeedSameResult) {
  const Data d = contact_data(3, 2.0, -0.5, 0.1, 0.02, 10);
  SparseOptions o;
  o.bootstrap = 50;
  const SparseResult a = sparse_regression(d.design(), o), b = sparse_regression(d.design(), o);
  EXPECT_EQ(a.coef, b.coef);
  // Bit for bit, NaN (a term outside the law has no interval) included.
  const auto same = [](const std::vector<double>& u, const std::vector<double>& v) {
    return u.size() == v.size() &&
           std::equal(u.begin(), u.end(), v.begin(), [](double p, double q) {
             return p == q || (std::isnan(p) && std::isnan(q));
           });
  };
  EXPECT_TRUE(same(a.lo, b.lo));
  EXPECT_TRUE(same(a.hi, b.hi));
  EXPECT_EQ(a.inclusion, b.inclusion);
}

// The interval is the chosen law's constants' (refitted on every resample), the inclusion the
// selection's stability (reselected on every resample): a chosen term's estimate lies inside
// its interval, a term outside the law has no interval, and a term of the law is reselected in
// most resamples. With two collinear powers of the penetration in play, a looser law of the
// same size may win some resamples: the two readings are told apart.
TEST(SparseRegression, IntervalsAreTheChosenLawsAndInclusionTheSelections) {
  for (std::uint64_t seed = 401; seed <= 405; ++seed) {
    const Data d = contact_data(seed, 2.0, -0.5, 0.10, 0.02);
    SparseOptions o;
    o.seed = seed;
    o.bootstrap = 100;
    const SparseResult r = sparse_regression(d.design(), o);
    ASSERT_GT(r.size, 0u) << seed;
    for (std::size_t j = 0; j < kTerms; ++j) {
      if (r.active[j]) {
        EXPECT_LE(r.lo[j], r.coef[j]) << "seed " << seed << " term " << j;
        EXPECT_GE(r.hi[j], r.coef[j]) << "seed " << seed << " term " << j;
        EXPECT_LT(r.lo[j], r.hi[j]) << "seed " << seed << " term " << j;
        EXPECT_GT(r.inclusion[j], 0.5) << "seed " << seed << " term " << j;
      } else {
        EXPECT_TRUE(std::isnan(r.lo[j]) && std::isnan(r.hi[j])) << "seed " << seed << " term " << j;
        EXPECT_GE(r.inclusion[j], 0.0);
        EXPECT_LT(r.inclusion[j], 0.5) << "seed " << seed << " term " << j;
      }
    }
  }
}

TEST(SparseRegression, RefusesBadDesignsAndOptionsByName) {
  Data d = contact_data(4, 1.0, 1.0, 0.0, 0.01, 3, 5);
  auto field_of = [](const SparseDesign& design, const SparseOptions& o) -> std::string {
    try {
      (void)sparse_regression(design, o);
    } catch (const InputError& e) {
      return e.field();
    }
    return "accepted";
  };
  SparseDesign bad = d.design();
  bad.x = bad.x.subspan(1);
  EXPECT_EQ(field_of(bad, {}), "x");
  bad = d.design();
  bad.group = bad.group.subspan(1);
  EXPECT_EQ(field_of(bad, {}), "group");
  const std::vector<std::size_t> one(d.y.size(), 7);
  bad = d.design();
  bad.group = one;
  EXPECT_EQ(field_of(bad, {}), "group");
  d.y[2] = NAN;
  EXPECT_EQ(field_of(d.design(), {}), "y");
  d.y[2] = 0;
  SparseOptions o;
  o.level = 1;
  EXPECT_EQ(field_of(d.design(), o), "level");
  const std::vector<double> wide(d.y.size() * (kMaxTerms + 1), 1.0);
  bad = d.design();
  bad.x = wide;
  bad.cols = kMaxTerms + 1;
  EXPECT_EQ(field_of(bad, {}), "cols");
  o = {};
  o.support = 1u << kTerms;  // a ninth term of an eight-term design
  EXPECT_EQ(field_of(d.design(), o), "support");
}

// A named law (SparseOptions::support) is fitted as named: the true term beside a wrong one
// (u v^2, which the truth lacks) and in noise alone, where selection would keep nothing. Its
// coefficients are subset_fit's, its held-out predictions those of the same folds, and the
// bootstrap refits that support only.
TEST(SparseRegression, ANamedSupportIsFittedWithoutSelection) {
  const std::uint32_t named = (1u << 1) | (1u << 5);
  for (const double a : {2.0, 0.0}) {
    const Data d = contact_data(301, a, 0.0, 0.10, 0.02);
    SparseOptions o;
    o.seed = 301;
    o.bootstrap = 50;
    o.support = named;
    const SparseResult r = sparse_regression(d.design(), o);
    EXPECT_EQ(r.size, 2u) << "a = " << a;
    for (std::size_t j = 0; j < kTerms; ++j) {
      EXPECT_EQ(r.active[j], (named >> j & 1u) != 0) << "term " << j;
      if (!(named >> j & 1u))
        EXPECT_TRUE(std::isnan(r.lo[j]) && std::isnan(r.hi[j])) << "term " << j;
      EXPECT_EQ(r.inclusion[j], (named >> j & 1u) ? 1.0 : 0.0) << "term " << j;
    }
    EXPECT_EQ(r.coef, subset_fit(d.design(), named));
    EXPECT_TRUE(std::isfinite(r.cv_error[0]) && std::isfinite(r.cv_error[2]));
    EXPECT_FALSE(std::isfinite(r.cv_error[1])) << "no other subset is scored";
    if (a > 0) {
      EXPECT_NEAR(r.coef[1], a, 0.05 * a);  // the true term, beside a term the truth lacks
      EXPECT_LT(r.lo[1], r.hi[1]);
      EXPECT_LT(r.cv_error[2], r.cv_error[0]);
    } else {
      EXPECT_GE(r.cv_error[2], r.cv_error[0]) << "in noise the named law predicts no better";
    }
  }
}

}  // namespace
}  // namespace ricochet::stats
