// Synthetic impacts with known velocities for the reconstruction tests.
//
// Free flight with velocity vin at t0 (contact start), a contact whose acceleration is a half sine
// (the force starts and ends at zero, as in sand: the gentlest onset, the hardest to detect)
// until t1 where the velocity is vout, then free flight again. Gravity acts throughout.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

#include "kinematics/reconstruct.hpp"

namespace ricochet::test {

struct SyntheticImpact {
  Vel3 vin{2.9, -2.3, -65}, vout{3.05, 0.86, -42};  // paper Table 2 cylinder means
  double t0 = 0.0513, t1 = 0.0813, g = 9.81;        // 30 ms contact, off the frame grid
  double xc = 0.2, yc = 0.08, thc = 0.3;            // state at t0 (centre one radius above y = 0)

  /// Exact centre position and angle at time t.
  void state(double t, double& x, double& y, double& th) const {
    const double T = t1 - t0, pi = std::numbers::pi;
    // Integral over [0, tau] of the velocity ramp (1 - cos(pi s / T)) / 2.
    auto ramp = [&](double tau) { return tau / 2 - T / (2 * pi) * std::sin(pi * tau / T); };
    if (t <= t0) {
      const double d = t - t0;
      x = xc + vin[0] * d;
      y = yc + vin[1] * d - 0.5 * g * d * d;
      th = thc + vin[2] * d;
      return;
    }
    const double tau = std::min(t, t1) - t0;
    x = xc + vin[0] * tau + (vout[0] - vin[0]) * ramp(tau);
    y = yc + vin[1] * tau - 0.5 * g * tau * tau + (vout[1] - vin[1] + g * T) * ramp(tau);
    th = thc + vin[2] * tau + (vout[2] - vin[2]) * ramp(tau);
    if (t <= t1) return;
    const double d = t - t1;
    x += vout[0] * d;
    y += vout[1] * d - 0.5 * g * d * d;
    th += vout[2] * d;
  }

  /// Ballistic vertical velocities at other times than the window ends (what a fit evaluated at
  /// a detected window end estimates).
  double vin_y_at(double t) const { return vin[1] - g * (t - t0); }
  double vout_y_at(double t) const { return vout[1] - g * (t - t1); }

  /// Video track as CSV in px: centre and an eccentric mark at `mark_r` [m], each pointed with
  /// Gaussian noise of `noise_px` then rounded to whole pixels, `fps` frames per second.
  std::string csv(double fps, double t_end, double pixel_m, double noise_px, unsigned seed,
                  double mark_r = 0.05) const {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0, noise_px);
    std::ostringstream s;
    s.precision(12);
    s << "# synthetic impact, seed " << seed << "\nt[s],x[px],y[px],mark_x[px],mark_y[px]\n";
    for (int i = 0;; ++i) {
      const double t = i / fps;
      if (t > t_end) break;
      double x, y, th;
      state(t, x, y, th);
      const double mx = x + mark_r * std::cos(th), my = y + mark_r * std::sin(th);
      auto px = [&](double v) { return std::round(v / pixel_m + n(rng)); };
      s << t << "," << px(x) << "," << px(y) << "," << px(mx) << "," << px(my) << "\n";
    }
    return s.str();
  }

  /// Noise-free time series with theta given directly (as from a LIGGGHTS dump).
  kinematics::Track series(double dt, double t_end) const {
    kinematics::Track tr;
    tr.source = "synthetic series";
    for (int i = 0; i * dt <= t_end; ++i) {
      double x, y, th;
      state(i * dt, x, y, th);
      tr.t.push_back(i * dt);
      tr.x.push_back(x);
      tr.y.push_back(y);
      tr.theta.push_back(th);
    }
    return tr;
  }
};

}  // namespace ricochet::test
