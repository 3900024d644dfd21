// The contact numbers of a track (stats/track_summary.hpp) on a hand-made one: free flight under
// gravity, a triangle force pulse of known peak and length, a penetration that peaks and comes
// back, and grains that still touch the block after the rebound. Every expected number is
// worked out here from the pulse's formula, not from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "impact/block_track.hpp"
#include "stats/track_summary.hpp"

namespace ricochet {
namespace {

constexpr double kG = 9.81;
constexpr double kDt = 5e-4;   // record interval [s]
constexpr double kTc = 0.020;  // peak of the pulse [s], on the grid
constexpr double kHalf = 0.005;
constexpr double kPeak = 1000;  // [N]
constexpr double kMass = 3.0;   // [kg]
constexpr double kInertia = 0.01;

// Records every kDt from 0 to 40 ms, but for one gap of 2 kDt at 5 ms (the largest interval). A
// block of kMass falling freely (vx 2 m/s, vy -3 m/s at t = 0, spin -50 rad/s) until the pulse.
// The pulse: fcy = kPeak (1 - |t - kTc| / kHalf) over |t - kTc| < kHalf, fcx = fcy / 4, torque =
// -fcy / 10 N*m. Penetration: -35 mm at t = 0 rising at 2 m/s to 5 mm at kTc, back to 3 mm at
// kTc + kHalf, then falling at 2 m/s as the block flies off. After the pulse: 3 N touches at kTc
// + 5.0, 5.5 and 6.0 ms (below 0.2 m g = 5.886 N, next to the pulse) and a 10 N touch at kTc +
// 10 ms (above it, but apart).
BlockTrack pulse_track() {
  BlockTrack tr;
  for (int k = 0; k <= 80; ++k) {
    if (k == 11) continue;  // the gap: 5.0 -> 6.0 ms
    const double t = k * kDt;
    const double vx = 2.0, vy = -3.0 - kG * t, w = -50.0;
    double f = std::abs(t - kTc) < kHalf ? kPeak * (1 - std::abs(t - kTc) / kHalf) : 0.0;
    const double after = t - kTc;
    if (std::abs(after - 0.0050) < 1e-9 || std::abs(after - 0.0055) < 1e-9 ||
        std::abs(after - 0.0060) < 1e-9)
      f = 3.0;
    if (std::abs(after - 0.010) < 1e-9) f = 10.0;
    double pen;
    if (t <= kTc)
      pen = 0.005 - 2.0 * (kTc - t);  // -35 mm at t = 0, 5 mm at the peak
    else if (t <= kTc + kHalf)
      pen = 0.005 - 0.002 * (t - kTc) / kHalf;
    else
      pen = 0.003 - 2.0 * (t - kTc - kHalf);
    tr.t.push_back(t);
    tr.x.push_back(vx * t);
    tr.y.push_back(0.1 - 3.0 * t - 0.5 * kG * t * t);
    tr.theta.push_back(w * t);
    tr.vx.push_back(vx);
    tr.vy.push_back(vy);
    tr.w.push_back(w);
    tr.fcx.push_back(f / 4);
    tr.fcy.push_back(f);
    tr.penetration.push_back(pen);
    tr.ke_block.push_back(0.5 * kMass * (vx * vx + vy * vy) + 0.5 * kInertia * w * w);
    tr.ke_grains.push_back(0.0);
    tr.torque.push_back(-f / 10);
    tr.overlap_d_max.push_back(0.01 + 0.06 * f / kPeak);
  }
  return tr;
}

TEST(TrackSummary, TrianglePulseGivesItsKnownNumbers) {
  const BlockTrack tr = pulse_track();
  const stats::TrackSummary s = stats::summarize_track(tr, "pulse");
  EXPECT_EQ(s.id, "pulse");
  EXPECT_EQ(s.records, 80u);
  EXPECT_NEAR(s.max_interval_s, 2 * kDt, 1e-12);
  // No mass in the file: from the free flight, exactly (the energies are exact here).
  EXPECT_EQ(s.block_mass_source, "free flight");
  EXPECT_NEAR(s.block_mass_kg, kMass, 1e-9);
  // Above 0.2 m g = 5.886 N: |t - kTc| < kHalf (1 - 5.886 / 1000) = 4.9706 ms, so on the 0.5 ms
  // grid the samples kTc - 4.5 ms ... kTc + 4.5 ms; the 3 N touches and the apart 10 N one are
  // outside.
  EXPECT_NEAR(s.contact_start_s, kTc - 0.0045, 1e-12);
  EXPECT_NEAR(s.contact_end_s, kTc + 0.0045, 1e-12);
  EXPECT_NEAR(s.contact_duration_s, 0.009, 1e-12);
  // Every nonzero force: the pulse's first sample (kTc - 4.5 ms) to the 10 N touch.
  EXPECT_NEAR(s.first_touch_s, kTc - 0.0045, 1e-12);
  EXPECT_NEAR(s.last_touch_s, kTc + 0.010, 1e-12);
  EXPECT_NEAR(s.peak_normal_force_N, kPeak, 1e-9);
  EXPECT_NEAR(s.peak_tangential_force_N, kPeak / 4, 1e-9);
  EXPECT_NEAR(s.peak_torque_Nm, kPeak / 10, 1e-9);
  EXPECT_NEAR(s.max_penetration_m, 0.005, 1e-12);
  // At the window's end, kTc + 4.5 ms: 5 mm - 2 mm x 4.5 / 5 = 3.2 mm; recovery 1.8 mm.
  EXPECT_NEAR(s.final_penetration_m, 0.0032, 1e-12);
  EXPECT_NEAR(s.elastic_recovery_m, 0.0018, 1e-12);
  EXPECT_NEAR(s.max_overlap_d, 0.07, 1e-12);
  // The window's records are 0.5 ms apart and carry 1000 (1 - k / 10) N, k = -9..9 half-ms from
  // the peak: 10,000 N in all. The penetration is negative at kTc - 4.5 ... - 3.0 ms (-4 ... -1
  // mm; 0 at kTc - 2.5 ms), where the force is 100 + 200 + 300 + 400 = 1,000 N: a share of 0.1.
  EXPECT_NEAR(s.lift_above_surface, 0.1, 1e-12);
}

TEST(TrackSummary, TheFilesMassDecidesTheCriterionAndWithoutOneAnyTouchCounts) {
  BlockTrack tr = pulse_track();
  // A heavier block in the file: 0.2 m g = 196.2 N, |t - kTc| < 4.019 ms: +-4.0 ms on the grid.
  tr.block_mass_kg = 100.0;
  stats::TrackSummary s = stats::summarize_track(tr, "heavy");
  EXPECT_EQ(s.block_mass_source, "file");
  EXPECT_NEAR(s.contact_duration_s, 0.008, 1e-12);
  // No mass anywhere (no kinetic energy): any nonzero force, so the adjacent 3 N touches join
  // the window (to kTc + 6.0 ms) and the apart 10 N one does not.
  tr.block_mass_kg = std::numeric_limits<double>::quiet_NaN();
  for (auto& e : tr.ke_block) e = std::nan("");
  s = stats::summarize_track(tr, "massless");
  EXPECT_EQ(s.block_mass_source, "unknown");
  EXPECT_NEAR(s.contact_start_s, kTc - 0.0045, 1e-12);
  EXPECT_NEAR(s.contact_end_s, kTc + 0.006, 1e-12);
}

// The impact proper: from the window's start to the first record after the peak whose force is
// at most m g. On the pulse (m = 3 kg from the free flight, m g = 29.43 N): 1000 (1 - |dt| / 5
// ms) <= 29.43 from |dt| = 4.853 ms, so the record at kTc + 5.0 ms (a 3 N touch); the window
// starts at kTc - 4.5 ms. The block's vy is made to rise through the pulse, from its free-flight
// value at the window's start to +0.3 m/s at kTc + 4.5 ms, then to fall under gravity.
TEST(TrackSummary, TheImpactEndsWhereTheForceFallsToTheWeight) {
  BlockTrack tr = pulse_track();
  const double t0 = kTc - 0.0045, t1 = kTc + 0.0045;
  const double vy0 = -3.0 - kG * t0;
  for (std::size_t i = 0; i < tr.size(); ++i) {
    const double t = tr.t[i];
    if (t > t0 + 1e-12)
      tr.vy[i] = t <= t1 + 1e-12 ? vy0 + (t - t0) * (0.3 - vy0) / (t1 - t0) : 0.3 - kG * (t - t1);
  }
  stats::TrackSummary s = stats::summarize_track(tr, "pulse");
  EXPECT_NEAR(s.impact_duration_s, 0.0095, 1e-12);
  const double vy_end = 0.3 - kG * 0.0005;
  EXPECT_NEAR(s.vy_impact_end_mps, vy_end, 1e-12);
  EXPECT_NEAR(s.impact_restitution, vy_end / -vy0, 1e-12);
  // A 100 kg block (m g = 981 N): the first record after the peak, kTc + 0.5 ms (900 N), ends
  // it; its window (above 196.2 N) starts at kTc - 4.0 ms.
  tr.block_mass_kg = 100.0;
  s = stats::summarize_track(tr, "heavy");
  EXPECT_NEAR(s.impact_duration_s, 0.0045, 1e-12);
  // No mass: no weight to compare with.
  tr.block_mass_kg = std::numeric_limits<double>::quiet_NaN();
  for (auto& e : tr.ke_block) e = std::nan("");
  s = stats::summarize_track(tr, "massless");
  EXPECT_TRUE(std::isnan(s.impact_duration_s));
  EXPECT_TRUE(std::isnan(s.vy_impact_end_mps));
  EXPECT_TRUE(std::isnan(s.impact_restitution));
}

// How long the bed presses after the peak: the unbroken run of records after it whose force,
// averaged over +-1 ms (5 records of the pulse's 0.5 ms grid), stays above 2 m g = 58.86 N (m =
// 3 kg). Record k half-ms after the peak carries f_k = 1000 sqrt(17/16) (1 - k/10) N for k < 10
// (fcx = fcy / 4), the 3 N touches at k = 10, 11, 12 (3.09 N) and 0 beyond. The average at k = 10
// is (f_8 + f_9 + 3 x 3.09) / 5 = 63.7 N, above, but the run ends with the contact window, at k =
// 9 (the touches are below 0.2 m g): 4.5 ms.
// A force of 80 N held from k = 10 to 30 (a bed that springs back as a whole): the average at k =
// 29 is 4 x 80 / 5 = 64 N, at k = 30 48 N: 14.5 ms. A single 20 N record at k = 20 (the grains'
// chatter) averages to 68 N and does not break it; five (k = 19..23) do: at k = 18 the average is
// (3 x 80 + 2 x 20) / 5 = 56 N, at k = 17 68 N: 8.5 ms. A 100 kg block (2 m g = 1962 N, above
// the whole pulse): 0.
TEST(TrackSummary, TheBedsPressAfterThePeakIsTimedAboveTwiceTheWeight) {
  BlockTrack tr = pulse_track();
  EXPECT_NEAR(stats::summarize_track(tr, "pulse").above_two_weights_after_peak_s, 0.0045, 1e-12);
  const auto set_after = [&tr](double from_s, double to_s, double f) {
    for (std::size_t i = 0; i < tr.size(); ++i) {
      const double after = tr.t[i] - kTc;
      if (after > from_s - 1e-9 && after < to_s + 1e-9) {
        tr.fcy[i] = f;
        tr.fcx[i] = 0.0;
      }
    }
  };
  set_after(0.005, 0.015, 80.0);
  EXPECT_NEAR(stats::summarize_track(tr, "springs back").above_two_weights_after_peak_s, 0.0145,
              1e-12);
  set_after(0.010, 0.010, 20.0);
  EXPECT_NEAR(stats::summarize_track(tr, "chatter").above_two_weights_after_peak_s, 0.0145, 1e-12);
  set_after(0.0095, 0.0115, 20.0);
  EXPECT_NEAR(stats::summarize_track(tr, "dips").above_two_weights_after_peak_s, 0.0085, 1e-12);
  tr.block_mass_kg = 100.0;
  EXPECT_EQ(stats::summarize_track(tr, "heavy").above_two_weights_after_peak_s, 0.0);
  tr.block_mass_kg = std::numeric_limits<double>::quiet_NaN();
  for (auto& e : tr.ke_block) e = std::nan("");
  EXPECT_TRUE(std::isnan(stats::summarize_track(tr, "massless").above_two_weights_after_peak_s));
}

TEST(TrackSummary, AnEstimatedForceBearsOnlyAboveTwiceItsStandardError) {
  // A force from tracked accelerations carries sigma_fcx, sigma_fcy: the criterion becomes
  // max(0.2 m g, 2 hypot(sigma_fcx, sigma_fcy)). The pulse's record k half-intervals from its
  // peak has |(fcx, fcy)| = 1030.8 (1 - k / 10) N: 103.1 N at k = 9, 206.2 at 8, 309.2 at 7.
  BlockTrack tr = pulse_track();
  auto duration = [&](double sx, double sy) {
    tr.sigma_fcx.assign(tr.size(), sx);
    tr.sigma_fcy.assign(tr.size(), sy);
    return stats::summarize_track(tr, "video").contact_duration_s;
  };
  EXPECT_NEAR(duration(40, 30), 0.009, 1e-12);   // 100 N: k <= 9, as without a standard error
  EXPECT_NEAR(duration(80, 60), 0.008, 1e-12);   // 200 N: k <= 8
  EXPECT_NEAR(duration(120, 90), 0.007, 1e-12);  // 300 N: k <= 7
}

TEST(TrackSummary, LegacyColumnsAndAnEmptyTrackGiveNaNNotNumbers) {
  BlockTrack tr = pulse_track();
  for (auto& v : tr.torque) v = std::nan("");
  for (auto& v : tr.overlap_d_max) v = std::nan("");
  const stats::TrackSummary s = stats::summarize_track(tr, "old");
  EXPECT_TRUE(std::isnan(s.peak_torque_Nm));
  EXPECT_TRUE(std::isnan(s.max_overlap_d));
  EXPECT_NEAR(s.peak_normal_force_N, kPeak, 1e-9);
  EXPECT_NEAR(s.lift_above_surface, 0.1, 1e-12);
  for (auto& v : tr.penetration) v = std::nan("");
  EXPECT_TRUE(std::isnan(stats::summarize_track(tr, "no depth").lift_above_surface));
  const stats::TrackSummary e = stats::summarize_track(BlockTrack{}, "empty");
  EXPECT_EQ(e.records, 0u);
  EXPECT_TRUE(std::isnan(e.contact_duration_s));
  EXPECT_TRUE(std::isnan(e.max_interval_s));
}

}  // namespace
}  // namespace ricochet
