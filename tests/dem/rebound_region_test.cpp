// The grain calibration's rebound region (src-ext/rebound_region.hpp), without LIGGGHTS: which
// impacts count as a rebound or not, and a calibration whose best V_out match lies where the
// synthetic bed gives no rebound must move out of that region, while the same campaign without
// the constraint lands in it (so the constraint, not the surrogate, moves the point).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "campaign_store.hpp"
#include "common/error.hpp"
#include "dem_support.hpp"
#include "grain_calibration.hpp"
#include "rebound_region.hpp"
#include "support/temp_dir_test.hpp"
#include "synthetic_campaign.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::dem;
using dem::test::decks;
using dem::test::make_campaign;
using dem::test::target_set;

CampaignEntry entry(const std::string& id, const std::string& status) {
  CampaignEntry e;
  e.id = id;
  e.status = status;
  return e;
}

// A rerun on a longer bed replaces its end-wall original; an end wall without one, a timeout and
// a no_rebound count as no rebound; a crash is not an outcome.
TEST(ReboundTally, CountsAnEndWallOnlyWithoutItsLongerRerunAndSkipsCrashes) {
  const std::vector<CampaignEntry> index = {
      entry("a-x0.26", "end_wall"), entry("a-x0.26-Lx1.5", "rebound"), entry("a-x0.32", "end_wall"),
      entry("b-x0.26", "timeout"),  entry("b-x0.32", "no_rebound"),    entry("b-x0.38", "crashed"),
      entry("c-x0.26", "rebound")};
  // The design point is the id's first letter: a, b, c have mu_gg 0.5, 0.6, 0.7.
  const std::map<char, std::string> mu_of = {{'a', "0.5"}, {'b', "0.6"}, {'c', "0.7"}};
  std::map<std::string, std::map<std::string, std::string>> grain;
  for (const auto& e : index) grain[e.id]["bed.mu_gg"] = mu_of.at(e.id[0]);
  GrainCalibrationResult r;
  r.source = "campaign.h5";
  r.parameters = {"bed.mu_gg"};
  tally_rebounds(r, index, grain);
  ASSERT_EQ(r.rebound_points.size(), 3u);
  const auto& a = r.rebound_points[0];
  EXPECT_EQ(a.x, std::vector<double>{0.5});
  EXPECT_EQ(a.counted, 2u);
  EXPECT_EQ(a.rebounds, 1u);
  EXPECT_EQ(a.missed, std::vector<std::string>{"a-x0.32"});
  const auto& b = r.rebound_points[1];
  EXPECT_EQ(b.counted, 2u);
  EXPECT_EQ(b.rebounds, 0u);
  EXPECT_EQ(r.rebound_points[2].rebounds, 1u);
}

class ReboundRegion : public ricochet::test::TempDirTest {
 protected:
  ReboundRegion() : TempDirTest("dem-rebound-region") {}
};

// The target (mu_gg 0.78, mur_gb 0.30: synthetic_campaign.hpp) inside a corner of the box where
// every impact times out: mu_gg > 0.70 and mur_gb < 0.36.
TEST_F(ReboundRegion, KeepsTheCalibratedPointWhereTheDesignRebounds) {
  const auto stuck = [](double mu, double mur) { return mu > 0.70 && mur < 0.36; };
  const std::string path = make_campaign(dir_, 24, {}, {}, [&](double mu, double mur, double) {
    return stuck(mu, mur) ? "timeout" : "rebound";
  });
  std::size_t stuck_points = 0;
  for (const auto& e : read_campaign_index(path)) stuck_points += e.status == "timeout";
  stuck_points /= 3;
  ASSERT_GE(stuck_points, 3u);
  GrainCalibrationOptions o;
  o.sobol_n = 2000;
  o.search_n = 8000;
  const auto r = calibrate_grains(path, decks(), target_set(), o);
  ASSERT_EQ(r.rebound_points.size(), 24u);
  std::size_t none = 0;
  for (const auto& t : r.rebound_points) {
    EXPECT_EQ(t.counted, 3u);
    EXPECT_TRUE(t.rebounds == 0 || t.rebounds == 3);
    EXPECT_EQ(t.rebounds == 0, stuck(t.x[1], t.x[2]));
    none += t.rebounds == 0;
  }
  EXPECT_EQ(none, stuck_points);
  EXPECT_EQ(r.rebound_threshold, GrainCalibrationOptions{}.rebound_threshold);
  EXPECT_GE(r.best_rebound, r.rebound_threshold);
  EXPECT_GT(r.rebound_loo_agreement, 0.75);
  EXPECT_GT(r.rebound_box_fraction, 0.3);
  EXPECT_LT(r.rebound_box_fraction, 0.95);
  EXPECT_LE(r.admissible_fraction, r.rebound_box_fraction);
  // Out of the corner (at 0.5 the search would sit on the indicator's blurred edge, which runs a
  // few hundredths inside the corner).
  EXPECT_FALSE(stuck(r.best[1], r.best[2])) << r.best[1] << " " << r.best[2];
  // Its figure beside the other three.
  const auto files = write_grain_calibration_figures(r, dir_.string());
  ASSERT_EQ(files.size(), 4u);
  EXPECT_EQ(files.back(), dir_.string() + "/grains_rebound.svg");
  EXPECT_GT(std::filesystem::file_size(files.back()), 1000u);
  // Without the region the surrogate of the rebounds alone goes into the corner, at the target.
  o.rebound_threshold = 0;
  const auto free = calibrate_grains(path, decks(), target_set(), o);
  EXPECT_TRUE(std::isnan(free.best_rebound));
  EXPECT_TRUE(stuck(free.best[1], free.best[2])) << free.best[1] << " " << free.best[2];
}

TEST_F(ReboundRegion, IsNoConstraintWhenEveryImpactReboundedAndAThresholdOutOfRangeIsAnError) {
  const std::string path = make_campaign(dir_, 8);
  GrainCalibrationOptions o;
  o.sobol_n = 1000;
  o.search_n = 1000;
  const auto r = calibrate_grains(path, decks(), target_set(), o);
  EXPECT_EQ(r.rebound_points.size(), 8u);
  EXPECT_EQ(r.rebound_threshold, 0.0);
  EXPECT_TRUE(std::isnan(r.best_rebound));
  EXPECT_EQ(r.admissible_fraction, 1.0);
  EXPECT_EQ(write_grain_calibration_figures(r, dir_.string()).size(), 3u);  // no region figure
  o.rebound_threshold = 1.0;
  try {
    calibrate_grains(path, decks(), target_set(), o);
    FAIL() << "a threshold of 1 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--rebound-threshold");
  }
}

}  // namespace
