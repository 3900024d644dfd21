// The plain scalar reference implementation of the paper's law that every speed target is
// measured against, in the same run (./run.sh bench): one collision at a time, array-of-structs
// state, Garcia et al. (2020) Eq. 3, 5, 6 for a disc, velocity Verlet, and 5 ms of free flight
// simulated after the last contact (how a straightforward script decides the rebound is over).
#pragma once

#include <algorithm>
#include <cmath>

#include "engine/engine.hpp"

namespace ricochet::bench {

inline Vel3 plain_scalar_collision(double en2, double mu, double muR, const Vel3& vin, double dt) {
  const double m = 13.9, I = 0.0445, R = 0.08, g = 9.81, kn = 1e7, kt = 1e7, kr = 1e8;
  struct State {
    double x, y, vx, vy, w, ax, ay, aw;
  } s{0.0, R, vin[0], vin[1], vin[2], 0.0, -g, 0.0};
  double fn = 0, ft = 0, M = 0, h_prev = 0, t = 0, t_sep = -1;
  bool touched = false;
  while (t < 0.5) {
    s.x += s.vx * dt + 0.5 * s.ax * dt * dt;
    s.y += s.vy * dt + 0.5 * s.ay * dt * dt;
    const double vxh = s.vx + 0.5 * s.ax * dt, vyh = s.vy + 0.5 * s.ay * dt,
                 wh = s.w + 0.5 * s.aw * dt;
    const double h = std::max(R - s.y, 0.0);
    double Fx = 0, Fy = -m * g, T = 0;
    if (h > 0) {
      touched = true;
      t_sep = -1;
      const double dh = h - h_prev;
      fn = dh >= 0 ? fn + kn * dh : std::min(fn, en2 * kn * h);
      fn = std::max(fn, 0.0);
      const double lever = R - 0.5 * h;
      const double vt = vxh + wh * lever;
      ft = std::clamp(ft - kt * vt * dt, -mu * fn, mu * fn);
      M = std::clamp(M - kr * wh * dt, -muR * lever * fn, muR * lever * fn);
      Fx += ft;
      Fy += fn;
      T += lever * ft + M;
    } else {
      fn = ft = M = 0;
      if (touched && t_sep < 0) t_sep = t;
    }
    h_prev = h;
    s.ax = Fx / m;
    s.ay = Fy / m;
    s.aw = T / I;
    s.vx = vxh + 0.5 * s.ax * dt;
    s.vy = vyh + 0.5 * s.ay * dt;
    s.w = wh + 0.5 * s.aw * dt;
    t += dt;
    if (t_sep >= 0 && t - t_sep > 5e-3) break;
  }
  return {s.vx, s.vy, s.w};
}

/// The paper's mean cylinder incident state (section 4.3).
inline const CollisionCase kLabMean{{2.9, -2.3, -65.0}, 0.0};

}  // namespace ricochet::bench
