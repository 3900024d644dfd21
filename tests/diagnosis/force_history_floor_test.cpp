// The force histories' replicate floor (diagnosis/force_history.hpp, force_history_scatter):
// hand-made histories whose replicate differences are known, so that the pooled scatter is
// worked out by hand: two histories that differ by a constant 100 N leave 100 / sqrt(2) N each
// from their mean; a tangential force of 100 N on a cylinder (lowest point 0.08 m under the
// centre) makes a moment of 8 N m about that point; a history shifted in time is the same
// history once aligned at its contact's start.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "diagnosis/force_history.hpp"

namespace ricochet::diagnosis {
namespace {

constexpr double kDt = 2e-4;  // s, the campaigns' track interval

// A history of `records` records every kDt from t0, whose normal force is `fy` [N] on records
// [on, off) and 0 elsewhere, tangential force `fx` [N] on the same records, no torque.
MeasuredHistory history(std::size_t records, double t0, std::size_t on, std::size_t off, double fy,
                        double fx = 0) {
  MeasuredHistory h;
  for (std::size_t i = 0; i < records; ++i) {
    PathState p;
    p.t_s = t0 + kDt * static_cast<double>(i);
    h.path.push_back(p);
    const bool in = i >= on && i < off;
    h.fy_N.push_back(in ? fy : 0.0);
    h.fx_N.push_back(in ? fx : 0.0);
    h.torque_Nm.push_back(0.0);
  }
  return h;
}

// A set of `n` releases, all at one incident state (one replicate group) unless `distinct`.
ImpactSet releases(std::size_t n, bool distinct = false) {
  ImpactSet set;
  for (std::size_t i = 0; i < n; ++i) {
    Impact im;
    im.id = "R" + std::to_string(i);
    im.shape = "cylinder";
    im.vin = {2.9 + (distinct ? 0.1 * static_cast<double>(i) : 0.0), -2.3, -65};
    im.vout = {3.0, 0.5, -42};
    set.impacts.push_back(im);
  }
  return set;
}

// The floor of histories `h`, one replicate group (releases at one incident state), cylinder.
ForceHistoryScatter floor_of(const std::vector<std::optional<MeasuredHistory>>& h) {
  return force_history_scatter(releases(h.size()), h, Shape::cylinder());
}

TEST(ForceHistoryFloor, TwoReplicatesApartByAConstantLeaveItOverRootTwo) {
  const ForceHistoryScatter s =
      floor_of({history(400, 0.0, 50, 300, 500.0), history(400, 0.0, 50, 300, 600.0)});
  EXPECT_EQ(s.groups, 1u);
  EXPECT_EQ(s.histories, 2u);
  EXPECT_NEAR(s.rms[0], 100.0 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(s.rms[1], 0.0, 1e-12);
  EXPECT_NEAR(s.rms[2], 0.0, 1e-12);
}

TEST(ForceHistoryFloor, AHistoryShiftedInTimeIsTheSameOnceAligned) {
  // The same contact, started at three times and in three tracks of different origins.
  const ForceHistoryScatter s =
      floor_of({history(400, 0.0, 50, 300, 500.0), history(400, 0.013, 80, 330, 500.0),
                history(500, -0.2, 10, 260, 500.0)});
  EXPECT_EQ(s.histories, 3u);
  EXPECT_NEAR(s.rms[0], 0.0, 1e-9);
}

TEST(ForceHistoryFloor, ATangentialForceMakesItsMomentAboutTheLowestPoint) {
  const ForceHistoryScatter s =
      floor_of({history(400, 0.0, 50, 300, 500.0, 100.0), history(400, 0.0, 50, 300, 500.0, 0.0)});
  EXPECT_NEAR(s.rms[0], 0.0, 1e-12);
  EXPECT_NEAR(s.rms[1], 100.0 / std::sqrt(2.0), 1e-9);
  // torque 0 - (r_x F_y - r_y F_x) with r = (0, -0.08 m): 0.08 m x 100 N = 8 N m apart.
  EXPECT_NEAR(s.rms[2], 8.0 / std::sqrt(2.0), 1e-9);
}

TEST(ForceHistoryFloor, AContactLongerThanItsReplicateIsComparedWithFlight) {
  // The first contact ends 100 records earlier; its track goes on (no force), so over the
  // longer window it reads 0 against the second's 500 N.
  const ForceHistoryScatter s =
      floor_of({history(400, 0.0, 50, 200, 500.0), history(400, 0.0, 50, 300, 500.0)});
  // Grid: 0 .. 249 records' time (the longer window), 250 times; 100 of them apart by 500 N.
  EXPECT_EQ(s.samples, 250u);
  EXPECT_NEAR(s.rms[0], std::sqrt(100.0 * 500.0 * 500.0 / 2.0 / 250.0), 1e-6);
}

TEST(ForceHistoryFloor, NoReplicatesNoFloor) {
  const ImpactSet set = releases(2, /*distinct=*/true);
  const std::vector<std::optional<MeasuredHistory>> h = {history(400, 0.0, 50, 300, 500.0),
                                                         history(400, 0.0, 50, 300, 600.0)};
  const ForceHistoryScatter s = force_history_scatter(set, h, Shape::cylinder());
  EXPECT_EQ(s.groups, 0u);
  EXPECT_TRUE(std::isnan(s.rms[0]));
  // A group of two of which one has no history is no group either.
  const ForceHistoryScatter one = force_history_scatter(
      releases(2), {history(400, 0.0, 50, 300, 500.0), std::nullopt}, Shape::cylinder());
  EXPECT_EQ(one.groups, 0u);
  EXPECT_THROW((void)force_history_scatter(releases(3), h, Shape::cylinder()),
               std::invalid_argument);
}

// pooled_rms_se: with one sample per release the pooled mean square is the mean of the releases'
// squares, so its standard error must be the textbook sd / sqrt(m) of those squares (here 4, 9,
// 25: mean 38/3, sd 10.970, SE 6.3333), carried to the RMS by d sqrt(R) = dR / (2 sqrt(R)):
// 6.3333 / (2 sqrt(38/3)) = 0.88976. With unequal counts, a release of many samples weighs in
// as its count says (by hand from the ratio estimator: ss = (10, 40), n = (10, 20): R = 5/3,
// deviations -20/3 and +20/3, var R = 2 * (800/9) / 900 = 0.19753, SE(RMS) = 0.44444 / (2
// sqrt(5/3)) = 0.17213). A release without samples does not count; one release is no spread.
TEST(ForceHistoryError, ThePooledRmsStandardErrorIsTheRatioEstimators) {
  const std::vector<double> ss = {4, 9, 25};
  const std::vector<std::size_t> one = {1, 1, 1};
  EXPECT_NEAR(pooled_rms_se(ss, one), 6.333333333 / (2 * std::sqrt(38.0 / 3.0)), 1e-8);
  EXPECT_NEAR(pooled_rms_se(std::vector<double>{10, 40}, std::vector<std::size_t>{10, 20}),
              0.172133, 1e-5);
  EXPECT_NEAR(pooled_rms_se(std::vector<double>{10, 40, 0}, std::vector<std::size_t>{10, 20, 0}),
              0.172133, 1e-5);
  EXPECT_TRUE(std::isnan(pooled_rms_se(std::vector<double>{4}, std::vector<std::size_t>{1})));
  EXPECT_THROW(pooled_rms_se(ss, std::vector<std::size_t>{1, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace ricochet::diagnosis
