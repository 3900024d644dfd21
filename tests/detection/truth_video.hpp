// A video of the independent simulator's collision: what a lab's high-speed camera would give
// (paper section 2.3), made from a release's exact history (truth_sim.hpp, SetOptions::tracks)
// for `ricochet reconstruct --track-forces` to turn back into forces. The camera is an
// assumption stated in its options: a frame rate, Gaussian pointing noise on each pointed
// coordinate of the centre and of an eccentric mark (paper: "pointing ... the block's center and
// an eccentric point"), and a random phase of the frames against the contact.
//
// Between the history's records (every 0.2 ms) positions are cubic Hermite interpolants of the
// recorded positions and velocities (error below a fraction of a micrometre at the contact's
// accelerations); before the first record and after the last the block flies ballistically
// under `gravity_mps2` from the recorded state, for `flight_s` on each side.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "impact/block_track.hpp"

namespace ricochet::truth {

struct VideoOptions {
  double fps = 400;             ///< frames per second (the paper's camera: 400)
  double noise_m = 1e-3;        ///< sd of each pointed coordinate [m]
  double mark_radius_m = 0.05;  ///< centre to eccentric mark [m]
  double flight_s = 0.03;       ///< free flight filmed before and after the history [s]
  double gravity_mps2 = 9.81;   ///< the simulator's gravity (Numerics)
};

/// The video of one history as a track CSV (t[s], x[m], y[m], mark_x[m], mark_y[m]), y from
/// the ground surface; `seed` draws the noise and the frames' phase.
inline std::string video_csv(const BlockTrack& h, const VideoOptions& o, std::uint64_t seed) {
  const std::size_t n = h.size();
  if (n < 2) throw std::invalid_argument("video_csv: a history needs two records");
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, o.noise_m);
  const double frame = 1.0 / o.fps;
  const double phase = std::uniform_real_distribution<double>(0.0, frame)(rng);
  const double g = o.gravity_mps2;
  // Position (x, y, theta) at time t.
  auto state = [&](double t, double& x, double& y, double& th) {
    const std::size_t end = n - 1;
    // The record at or before t (the first or last outside the history).
    const std::size_t i =
        t <= h.t[0] ? 0
        : t >= h.t[end]
            ? end
            : static_cast<std::size_t>(std::upper_bound(h.t.begin(), h.t.end(), t) - h.t.begin()) -
                  1;
    if (t <= h.t[0] || t >= h.t[end]) {
      const double d = t - h.t[i];
      x = h.x[i] + h.vx[i] * d;
      y = h.y[i] + h.vy[i] * d - 0.5 * g * d * d;
      th = h.theta[i] + h.w[i] * d;
      return;
    }
    const double dt = h.t[i + 1] - h.t[i], s = (t - h.t[i]) / dt;
    const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
    const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
    auto hermite = [&](const std::vector<double>& p, const std::vector<double>& v) {
      return h00 * p[i] + h10 * dt * v[i] + h01 * p[i + 1] + h11 * dt * v[i + 1];
    };
    x = hermite(h.x, h.vx);
    y = hermite(h.y, h.vy);
    th = hermite(h.theta, h.w);
  };
  std::ostringstream s;
  s.precision(10);
  s << "# video of the independent simulator (tests/detection/truth_video.hpp): " << o.fps
    << " fps, pointing noise " << o.noise_m << " m, seed " << seed << "\n";
  s << "t[s],x[m],y[m],mark_x[m],mark_y[m]\n";
  const double t0 = h.t.front() - o.flight_s, t1 = h.t.back() + o.flight_s;
  for (long k = 0;; ++k) {
    const double t = t0 + phase + static_cast<double>(k) * frame;
    if (t > t1) break;
    double x, y, th;
    state(t, x, y, th);
    const double mx = x + o.mark_radius_m * std::cos(th), my = y + o.mark_radius_m * std::sin(th);
    s << t << "," << x + noise(rng) << "," << y + noise(rng) << "," << mx + noise(rng) << ","
      << my + noise(rng) << "\n";
  }
  return s.str();
}

}  // namespace ricochet::truth
