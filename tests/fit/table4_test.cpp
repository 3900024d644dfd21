// Paper Table 4 (Operator #2, per-release calibration of Eq. 7): cylinders e_n^2 = 0.15 +- 0.06.
// The per-release values of e_n^2 must reproduce it within 0.02 (mean and standard deviation);
// mu and mu_R are checked for what the analysis shows instead of the paper's single numbers:
// e_n^2 identified in every release, mu not identified in most.
#include <gtest/gtest.h>

#include "fit/fit.hpp"
#include "stats/stats.hpp"

namespace ricochet::fit {
namespace {

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

std::vector<double> values(const std::vector<ReleaseFit>& fits, const std::string& name) {
  std::vector<double> v;
  for (const auto& f : fits) v.push_back(f.value(name));
  return v;
}

TEST(Table4, CylinderRestitutionMatchesThePaper) {
  const ImpactSet set = read_impact_set(kLab + "cylinders.csv");
  FitOptions o;
  const auto fits = calibrate_releases(Model::paper(), Shape::cylinder(), set, o);
  ASSERT_EQ(fits.size(), 28u);
  const stats::Summary en2 = stats::summarize(values(fits, "en2"));
  EXPECT_NEAR(en2.mean, 0.15, 0.02);
  EXPECT_NEAR(en2.std, 0.06, 0.02);

  int en2_identified = 0, mu_identified = 0;
  for (const auto& f : fits) {
    en2_identified += f.interval("en2")->status == Identifiability::kIdentified;
    mu_identified += f.interval("mu")->status == Identifiability::kIdentified;
    // Every optimum is near-optimal by definition: intervals contain the reported value.
    for (const auto& iv : f.intervals) {
      EXPECT_LE(iv.lo, iv.value + 1e-12) << f.id << " " << iv.name;
      EXPECT_GE(iv.hi, iv.value - 1e-12) << f.id << " " << iv.name;
    }
  }
  EXPECT_EQ(en2_identified, 28);
  // The paper's mu = 0.23 +- 0.11 is a property of its optimiser's start, not of the data.
  EXPECT_LT(mu_identified, 14);
}

TEST(Table4, TriangleRowRunsWithTheOrientationAsNuisance) {
  // No reproduction target (the paper's triangle fits used measured incidence angles that the
  // data set does not contain); the per-release fits must be complete and within bounds.
  const ImpactSet set = read_impact_set(kLab + "triangles.csv");
  FitOptions o;
  o.intervals = false;
  const Model model = Model::paper();
  const auto fits = calibrate_releases(model, Shape::triangle(), set, o);
  ASSERT_EQ(fits.size(), 31u);
  for (const auto& f : fits) {
    EXPECT_EQ(f.alpha_source, "fitted");
    EXPECT_GE(f.value("en2"), 0.0);
    EXPECT_LE(f.value("en2"), 1.0);
    EXPECT_TRUE(std::isfinite(f.error));
  }
}

}  // namespace
}  // namespace ricochet::fit
