// The granular-impact fits (src-ext/granular_fits.hpp) on analytic data made independently of
// what the fits assume: Katsuragi-Durian trajectories integrated by RK4 with a fine step and
// sampled at an unrelated interval with noise; Uehara depths with a known exponent and noise; a
// heap profile with a known slope. No LIGGGHTS.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "granular_fits.hpp"
#include "rk4_penetration.hpp"

namespace {

using namespace ricochet::dem;

constexpr double kG = 9.81;

// Katsuragi & Durian 2007 Eq. (1), z positive down, integrated with classical RK4 at step
// dt_int and sampled every `every` steps, from z = 0 at speed v0 until z' < 0 (the stop).
struct Trajectory {
  std::vector<double> t, z;
};
Trajectory kd_rk4(double v0, double d1, double k_over_m, double dt_int, int every, double noise_m,
                  std::mt19937& rng) {
  auto acc = [&](double z, double v) { return kG - v * v / d1 - k_over_m * z; };
  std::normal_distribution<double> n(0.0, noise_m);
  Trajectory tr;
  // A short free fall before contact (z < 0): the record starts above the surface like the DEM's.
  double z = -v0 * 0.002, v = v0, t = 0;
  for (long i = 0; v > -1e-3; ++i) {
    if (i % every == 0) {
      tr.t.push_back(t);
      tr.z.push_back(z + (noise_m > 0 ? n(rng) : 0.0));
    }
    auto a_of = [&](double zz, double vv) { return zz < 0 ? kG : acc(zz, vv); };
    test::rk4_step(z, v, dt_int, a_of);
    t += dt_int;
  }
  return tr;
}

TEST(GranularFits, LeastSquaresRecoversALineAndRejectsCollinearColumns) {
  std::vector<double> one, x, y;
  for (int i = 0; i < 10; ++i) {
    one.push_back(1);
    x.push_back(i);
    y.push_back(2.0 + 0.5 * i);
  }
  const auto f = least_squares({one, x}, y);
  EXPECT_NEAR(f.beta[0], 2.0, 1e-12);
  EXPECT_NEAR(f.beta[1], 0.5, 1e-12);
  EXPECT_THROW(least_squares({x, x}, y), std::invalid_argument);
  EXPECT_THROW(least_squares({one, x}, std::vector<double>{1.0, 2.0}), std::invalid_argument);
}

TEST(GranularFits, LocalQuadraticDerivativesAreExactOnAParabolaWithUnevenSampling) {
  std::vector<double> t, z;
  double s = 0;
  for (int i = 0; i < 40; ++i) {
    s += 1e-4 * (1.0 + 0.3 * std::sin(i));  // uneven spacing
    t.push_back(s);
    z.push_back(0.01 + 2.0 * s - 0.5 * 30.0 * s * s);
  }
  const auto d = local_quadratic_derivatives(t, z, 4);
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR(d.v[i], 2.0 - 30.0 * t[i], 1e-7);
    EXPECT_NEAR(d.a[i], -30.0, 1e-4);
  }
}

TEST(GranularFits, KatsuragiDurianRecoveredFromNoiseFreeRk4Trajectory) {
  std::mt19937 rng(1);
  // RK4 at 1 us sampled every 37 us (the DEM records every 45 us: neither is assumed).
  const double d1 = 0.04, k_over_m = 2000.0, mass = 0.5;
  const auto tr = kd_rk4(3.0, d1, k_over_m, 1e-6, 37, 0.0, rng);
  const auto s = penetration_samples(tr.t, tr.z, 8, 0.1);
  ASSERT_GT(s.size(), 100u);
  const auto f = fit_katsuragi_durian(s, mass);
  EXPECT_NEAR(f.d1_m, d1, 1e-3 * d1);
  EXPECT_NEAR(f.k_over_m_per_s2, k_over_m, 1e-2 * k_over_m);
  EXPECT_NEAR(f.g_mps2, kG, 0.02 * kG);
  EXPECT_NEAR(f.k_Npm, mass * k_over_m, 1e-2 * mass * k_over_m);
  EXPECT_NEAR(f.drag_kg_per_m, mass / d1, 1e-3 * mass / d1);
}

TEST(GranularFits, KatsuragiDurianPooledOverSpeedsWithNoise) {
  // Five impact speeds (0.9 to 4.4 m/s, like drops from 0.05 to 1 m), 2 um of position noise
  // (a tenth of a grain's overlap): one d1 and one k for all, as the law claims.
  std::mt19937 rng(7);
  const double d1 = 0.03, k_over_m = 1500.0, mass = 0.51;
  std::vector<KdSample> pooled;
  for (double v0 : {0.99, 1.4, 1.98, 3.13, 4.43}) {
    const auto tr = kd_rk4(v0, d1, k_over_m, 2e-6, 23, 2e-6, rng);
    const auto s = penetration_samples(tr.t, tr.z, 10, 0.1);
    pooled.insert(pooled.end(), s.begin(), s.end());
  }
  const auto f = fit_katsuragi_durian(pooled, mass, 21.0);
  // Tolerances: 5 % on d1 and k, 10 % on g; and the truth within 4 standard errors.
  EXPECT_NEAR(f.d1_m, d1, 0.05 * d1);
  EXPECT_NEAR(f.k_over_m_per_s2, k_over_m, 0.05 * k_over_m);
  EXPECT_NEAR(f.g_mps2, kG, 0.1 * kG);
  EXPECT_LT(std::abs(f.d1_m - d1), 4 * f.d1_se + 1e-4 * d1);
  EXPECT_LT(std::abs(f.k_over_m_per_s2 - k_over_m), 4 * f.k_over_m_se + 1e-4 * k_over_m);
  // Imposing g removes one unknown: no worse.
  const auto fg = fit_katsuragi_durian(pooled, mass, 21.0, kG);
  EXPECT_NEAR(fg.d1_m, d1, 0.05 * d1);
  EXPECT_NEAR(fg.k_over_m_per_s2, k_over_m, 0.05 * k_over_m);
}

TEST(GranularFits, PenetrationPhaseStartsAtTheSurfaceAndEndsBeforeTheStop) {
  std::mt19937 rng(3);
  const auto tr = kd_rk4(2.0, 0.03, 1000.0, 1e-6, 50, 0.0, rng);
  const auto s = penetration_samples(tr.t, tr.z, 5, 0.2);
  ASSERT_FALSE(s.empty());
  EXPECT_GE(s.front().z_m, 0.0);
  EXPECT_NEAR(s.front().v_mps, 2.0, 0.05);
  for (const auto& x : s) EXPECT_GE(x.v_mps, 0.2 * s.front().v_mps);
}

TEST(GranularFits, UeharaExponentAndPrefactorRecovered) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.02);  // 2 % scatter of the depth
  const double rho_b = 7800, rho_g = 1600, D = 0.05, mu = 0.7;
  std::vector<double> H, d;
  for (int rep = 0; rep < 2; ++rep)
    for (double h : {0.05, 0.1, 0.2, 0.5, 1.0}) {
      // Uehara's law itself with exponent 1/3 (H = h + d solved by iteration).
      double dd = 0.01;
      for (int it = 0; it < 50; ++it) dd = uehara_depth_m(h + dd, rho_b, rho_g, D, mu);
      H.push_back(h + dd);
      d.push_back(dd * std::exp(noise(rng)));
    }
  const auto c = check_uehara(H, d, rho_b, rho_g, D, mu, 0.05);
  EXPECT_NEAR(c.fit.exponent, 1.0 / 3.0, 0.03);
  EXPECT_LT(std::abs(c.exponent_deviation), 4 * c.fit.exponent_se);
  EXPECT_TRUE(c.exponent_pass);
  EXPECT_NEAR(c.c_expected, 0.2, 1e-12);
  EXPECT_NEAR(c.c_fitted, 0.2, 0.01);
  EXPECT_LT(std::abs(c.c_fitted - 0.2), 4 * c.c_fitted_se);
}

TEST(GranularFits, UeharaCheckFailsOnAWrongExponent) {
  // d ~ H^0.45: the check must fail at tolerance 0.05 (it is a test, not a fit).
  std::vector<double> H, d;
  for (double h : {0.06, 0.12, 0.25, 0.5, 1.0}) {
    H.push_back(h);
    d.push_back(0.05 * std::pow(h, 0.45));
  }
  const auto c = check_uehara(H, d, 7800, 1600, 0.05, 0.7, 0.05);
  EXPECT_NEAR(c.fit.exponent, 0.45, 1e-9);
  EXPECT_FALSE(c.exponent_pass);
  EXPECT_THROW(
      fit_power_law(std::vector<double>{1.0, 1.0, 1.0}, std::vector<double>{1.0, 2.0, 3.0}),
      std::invalid_argument);
}

TEST(GranularFits, ReposeSlopeOfASyntheticHeap) {
  // Plateau 0.1 m high up to x = 0.05 m, then a 33 deg flank, then a thin runout; bins of 8 mm
  // with 2 mm of roughness.
  std::mt19937 rng(5);
  std::normal_distribution<double> rough(0.0, 0.002);
  const double tan_angle = std::tan(33.0 * std::numbers::pi / 180);
  std::vector<double> x, h;
  for (double xb = 0.004; xb < 0.4; xb += 0.008) {
    const double surface = std::max(0.004, std::min(0.1, 0.1 - tan_angle * (xb - 0.05)));
    x.push_back(xb);
    h.push_back(surface + rough(rng));
  }
  h[45] = std::nan("");  // an empty bin
  const auto s = fit_repose_slope(x, h);
  EXPECT_NEAR(s.angle_deg, 33.0, 1.5);
  EXPECT_LT(std::abs(s.angle_deg - 33.0), 4 * s.angle_se_deg);
  EXPECT_GE(s.n, 10u);
  EXPECT_GT(s.x_lo_m, 0.05);
  EXPECT_THROW(fit_repose_slope(std::vector<double>{0.0, 1.0}, std::vector<double>{1.0, 0.0}),
               std::invalid_argument);
}

}  // namespace
