// The residual map (diagnosis/residual_map.hpp): each sample goes to its branch and depth band,
// each release counts once per cell, the standard error is over releases, and a component not
// measured stays undefined rather than zero.
#include "diagnosis/residual_map.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ricochet::diagnosis {
namespace {

// A release pressed to depth `h_max` in 9 loading samples and pulled out in 9: the normal
// residual is `deep` on loading below 2/3 h_max and `out` on unloading; the moment is unmeasured.
ReleaseResidual release(double h_max, double deep, double out) {
  ReleaseResidual r;
  for (int i = 1; i <= 9; ++i) {
    ContactSample s;
    s.h_m = h_max * i / 9.0;
    s.loading = true;
    r.samples.push_back(s);
    r.residual.push_back({s.h_m >= 2.0 / 3.0 * h_max ? deep : 0.0, 10.0, NAN});
  }
  for (int i = 9; i >= 1; --i) {
    ContactSample s;
    s.h_m = h_max * i / 9.0 - 1e-9;
    s.loading = false;
    r.samples.push_back(s);
    r.residual.push_back({out, -10.0, NAN});
  }
  return r;
}

TEST(ResidualMap, EachReleaseCountsOnceAndTheErrorIsOverReleases) {
  const std::vector<ReleaseResidual> rs = {release(2e-3, -300.0, 50.0),
                                           release(5e-3, -500.0, 50.0)};
  const ResidualMap m = residual_map(rs);
  const ResidualCell& deep = m.cell[0][2];
  EXPECT_EQ(deep.releases, 2u);
  EXPECT_EQ(deep.samples, 8u);  // h = 6/9 .. 9/9 of h_max, four per release
  EXPECT_NEAR(deep.mean[0], -400.0, 1e-9);
  EXPECT_NEAR(deep.se[0], 100.0, 1e-9);  // sd(-300, -500) / sqrt(2)
  EXPECT_NEAR(m.cell[0][0].mean[0], 0.0, 1e-12);
  EXPECT_NEAR(m.cell[0][1].mean[1], 10.0, 1e-12);
  for (std::size_t d = 0; d < ResidualMap::kBands; ++d) {
    EXPECT_NEAR(m.cell[1][d].mean[0], 50.0, 1e-12) << d;
    EXPECT_NEAR(m.cell[1][d].se[0], 0.0, 1e-12) << d;
    EXPECT_NEAR(m.cell[1][d].mean[1], -10.0, 1e-12) << d;
    EXPECT_TRUE(std::isnan(m.cell[1][d].mean[2])) << d;  // the moment was not measured
  }
  const nlohmann::json j = to_json(m);
  EXPECT_TRUE(j["loading"][2]["mean"]["moment"].is_null());
  EXPECT_DOUBLE_EQ(j["loading"][2]["mean"]["normal"].get<double>(), -400.0);
  EXPECT_DOUBLE_EQ(j["unloading"][0]["h_over_hmax"][1].get<double>(), 1.0 / 3.0);
}

TEST(ResidualMap, AnEmptyCellIsUndefinedAndPrintedAsADash) {
  ReleaseResidual only_loading = release(3e-3, -100.0, 0.0);
  only_loading.samples.resize(9);
  only_loading.residual.resize(9);
  const std::vector<ReleaseResidual> rs = {only_loading};
  const ResidualMap m = residual_map(rs);
  EXPECT_EQ(m.cell[1][0].releases, 0u);
  EXPECT_TRUE(std::isnan(m.cell[1][0].mean[0]));
  EXPECT_TRUE(std::isnan(m.cell[0][2].se[0]));  // one release: no spread to estimate
  const std::string text = format_text(m);
  EXPECT_NE(text.find("unloading"), std::string::npos) << text;
  const auto rows = residual_map_rows(m);
  ASSERT_EQ(rows.size(), 4u);  // loading and unloading, normal and tangential: no moment row
  EXPECT_EQ(rows[2][0], "unloading");
  EXPECT_EQ(rows[2][2], "-");     // no unloading sample at all
  EXPECT_EQ(rows[0][4], "-100");  // one release: a mean without a standard error
  EXPECT_EQ(rows[1][1], "tangential [N]");
}

}  // namespace
}  // namespace ricochet::diagnosis
