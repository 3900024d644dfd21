// Contact force from tracked accelerations (kinematics/track_forces.hpp): exact on polynomial
// motion, the known half-sine contact force of the synthetic impact recovered within the
// smoothing bias the header states, and standard errors that match the scatter of many noisy
// tracks (so that the +-2 s.e. band a user sees means what it says).
#include "kinematics/track_forces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "synthetic_track.hpp"

namespace ricochet {
namespace {

using kinematics::Track;
using kinematics::track_with_forces;
using kinematics::TrackForceOptions;

constexpr double kMass = 13.9, kInertia = 0.0445;  // the lab cylinder (paper Fig. 4)

TrackForceOptions cylinder_options(std::size_t k = 2) {
  TrackForceOptions o;
  o.mass_kg = kMass;
  o.inertia_kgm2 = kInertia;
  o.half_window = k;
  return o;
}

// The half-sine contact force of test::SyntheticImpact at time t [N] (its velocity ramp
// (1 - cos(pi tau / T)) / 2 differentiated twice): zero outside the contact.
double true_fcy(const test::SyntheticImpact& s, double t) {
  const double T = s.t1 - s.t0, tau = t - s.t0;
  if (tau <= 0 || tau >= T) return 0;
  return kMass * (s.vout[1] - s.vin[1] + s.g * T) * std::numbers::pi / (2 * T) *
         std::sin(std::numbers::pi * tau / T);
}

TEST(TrackForces, ExactOnUniformlyAcceleratedMotion) {
  // x, y, theta quadratic in t: every local quadratic fit is exact, at the ends too.
  Track tr;
  for (int i = 0; i < 30; ++i) {
    const double t = 0.0025 * i + 0.0007 * (i % 3);  // uneven frame intervals
    tr.t.push_back(t);
    tr.x.push_back(0.1 + 3.0 * t - 0.5 * 40.0 * t * t);
    tr.y.push_back(0.3 - 2.0 * t + 0.5 * 150.0 * t * t);
    tr.theta.push_back(0.2 - 60.0 * t + 0.5 * 900.0 * t * t);
  }
  const BlockTrack b = track_with_forces(tr, 1e-3, 1e-2, cylinder_options());
  ASSERT_EQ(b.size(), tr.t.size());
  for (std::size_t i = 0; i < b.size(); ++i) {
    EXPECT_NEAR(b.fcx[i], kMass * -40.0, 1e-6);
    EXPECT_NEAR(b.fcy[i], kMass * (150.0 + 9.81), 1e-6);  // gravity added back: y is up
    EXPECT_NEAR(b.torque[i], kInertia * 900.0, 1e-8);
    EXPECT_NEAR(b.vx[i], 3.0 - 40.0 * tr.t[i], 1e-9);
    EXPECT_NEAR(b.w[i], -60.0 + 900.0 * tr.t[i], 1e-8);
  }
  EXPECT_DOUBLE_EQ(b.block_mass_kg, kMass);
}

TEST(TrackForces, HalfSineContactForceWithinTheSmoothingBias) {
  const test::SyntheticImpact s;
  const double peak = true_fcy(s, 0.5 * (s.t0 + s.t1));
  ASSERT_GT(peak, 2000.0);  // 2.5 kN for the paper's cylinder means
  // 0.5 ms frames (2000 fps): a 5-frame fit spans 2 ms of a 30 ms contact; the mean of a sine
  // over +-1 ms of its 60 ms period differs from its value by at most (pi 2/60)^2/6 = 0.2 %.
  const BlockTrack fine = track_with_forces(s.series(0.0005, 0.14), 0, 0, cylinder_options());
  double worst = 0;
  for (std::size_t i = 0; i < fine.size(); ++i)
    worst = std::max(worst, std::abs(fine.fcy[i] - true_fcy(s, fine.t[i])));
  // The largest miss is at the kinks of the force (its onset and end), where a 2 ms fit
  // straddles the jump of the force's slope: a few percent of the peak.
  EXPECT_LT(worst, 0.05 * peak);
  // 400 fps with k = 2 spans 10 ms: the peak is flattened, by more than the 2000 fps estimate.
  const BlockTrack coarse = track_with_forces(s.series(0.0025, 0.14), 0, 0, cylinder_options());
  double coarse_peak = 0, fine_peak = 0;
  for (double f : coarse.fcy) coarse_peak = std::max(coarse_peak, f);
  for (double f : fine.fcy) fine_peak = std::max(fine_peak, f);
  EXPECT_NEAR(fine_peak, peak, 0.01 * peak);
  EXPECT_LT(coarse_peak, fine_peak);
  EXPECT_GT(coarse_peak, 0.8 * peak);
  // Outside the contact (beyond one window of it) the force is zero: gravity is removed.
  for (std::size_t i = 0; i < coarse.size(); ++i) {
    if (coarse.t[i] > s.t0 - 0.006 && coarse.t[i] < s.t1 + 0.006) continue;
    EXPECT_NEAR(coarse.fcy[i], 0.0, 1e-6) << "t = " << coarse.t[i];
  }
}

TEST(TrackForces, StandardErrorsMatchTheScatterOfNoisyTracks) {
  // 2000 free flights with 1 mm pointing noise at 400 fps: the contact force of one interior
  // frame (true value 0) divided by its stated standard error must be N(0, 1). The sample sd of
  // 2000 z has a standard error of 1.6 %: +-7 % is 4 of them, and a wrong sd formula (e.g. a
  // missing factor 2 of the curvature) misses by 100 %.
  const test::SyntheticImpact s;
  std::mt19937_64 rng(20261129);
  std::normal_distribution<double> noise(0.0, 1e-3);
  double sum2 = 0;
  int inside = 0;
  const int n = 2000;
  for (int rep = 0; rep < n; ++rep) {
    Track tr = s.series(0.0025, 0.04);  // before the contact: free flight
    for (auto& v : tr.y) v += noise(rng);
    const BlockTrack b = track_with_forces(tr, 1e-3, 1e-2, cylinder_options());
    const std::size_t i = b.size() / 2;
    const double z = b.fcy[i] / b.sigma_fcy[i];
    sum2 += z * z;
    inside += std::abs(z) < 1.96;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 1.0, 0.07);
  EXPECT_NEAR(inside / double(n), 0.95, 0.02);
}

TEST(TrackForces, PenetrationFromTheShapeAndTheSurface) {
  Track tr;
  for (int i = 0; i < 7; ++i) {
    tr.t.push_back(0.001 * i);
    tr.x.push_back(0);
    tr.y.push_back(0.5 + 0.07);  // a disc of radius 0.08 m, 1 cm into a surface at y = 0.5
    tr.theta.push_back(0);
  }
  TrackForceOptions o = cylinder_options(1);
  o.surface_y_m = 0.5;
  const BlockTrack without = track_with_forces(tr, 1e-3, 1e-2, o);
  EXPECT_TRUE(std::isnan(without.penetration[3]));
  o.depth_below_centroid_m = [](double) { return 0.08; };
  const BlockTrack with = track_with_forces(tr, 1e-3, 1e-2, o);
  EXPECT_NEAR(with.penetration[3], 0.01, 1e-12);
}

TEST(TrackForces, RefusesWhatItCannotCompute) {
  const test::SyntheticImpact s;
  const Track tr = s.series(0.0025, 0.14);
  TrackForceOptions o = cylinder_options();
  o.mass_kg = 0;
  EXPECT_THROW(track_with_forces(tr, 1e-3, 1e-2, o), std::invalid_argument);
  o = cylinder_options();
  o.inertia_kgm2 = -1;
  EXPECT_THROW(track_with_forces(tr, 1e-3, 1e-2, o), std::invalid_argument);
  Track no_theta = tr;
  no_theta.theta.clear();  // without theta the inertia is not needed, the torque is NaN
  const BlockTrack b = track_with_forces(no_theta, 1e-3, 1e-2, o);
  EXPECT_TRUE(std::isnan(b.torque[3]));
  EXPECT_TRUE(std::isfinite(b.fcy[3]));
  Track short_track = tr;
  for (auto* c : {&short_track.t, &short_track.x, &short_track.y, &short_track.theta}) c->resize(4);
  EXPECT_THROW(track_with_forces(short_track, 1e-3, 1e-2, cylinder_options()),
               std::invalid_argument);
  EXPECT_THROW(track_with_forces(tr, 1e-3, 1e-2, cylinder_options(0)), std::invalid_argument);
}

}  // namespace
}  // namespace ricochet
