// One step of the engine for one lane, or for one vector of lanes: the arithmetic of velocity
// Verlet and of a vertex's contact with the ground, written once and shared by the generic batch
// loops (engine/lane_batch.hpp, T = double inside vectorised loops over the lane arrays) and the fused
// kernel (paper_kernel.hpp, T = Lanes held in registers). The effects' contact law is shared the
// same way (effects/normal.hpp, tangential.hpp, rolling.hpp). Internal to the engine.
//
// Integration (paper section 4.1; Verlet 1967), as in Rockable: positions with the previous
// accelerations, forces at the half-step velocities, then velocities completed.
#pragma once

#include <cmath>
#include <cstddef>

#include "effects/effect.hpp"

namespace ricochet::detail {

/// Lanes per chunk of the fused kernel: one AVX-512 register of doubles (GCC lowers it to
/// narrower vectors on machines without AVX-512).
inline constexpr std::size_t kChunk = 8;
using Lanes = double __attribute__((vector_size(kChunk * sizeof(double))));

inline double lane_sqrt(double v) {
  return std::sqrt(v);
}
inline Lanes lane_sqrt(Lanes v) {
  Lanes out;
  for (std::size_t k = 0; k < kChunk; ++k) out[k] = std::sqrt(v[k]);
  return out;
}

/// Velocity Verlet's first half: positions x, y [m] and orientation th [rad] from the previous
/// accelerations, and the half-step velocities vxh, vyh [m/s], wh [rad/s].
template <class T>
inline void verlet_first_half(T& x, T& y, T& th, T vx, T vy, T w, T ax, T ay, T aw, double dt,
                              T& vxh, T& vyh, T& wh) {
  const double half_dt = 0.5 * dt, half_dt2 = 0.5 * dt * dt;
  x += vx * dt + ax * half_dt2;
  y += vy * dt + ay * half_dt2;
  th += w * dt + aw * half_dt2;
  vxh = vx + ax * half_dt;
  vyh = vy + ay * half_dt;
  wh = w + aw * half_dt;
}

/// One vertex's contact: overlap h [m], contact point relative to the centre of mass (rcx, rcy)
/// [m], lever l [m] (paper Eq. 6), normal and tangential velocities of the contact point vn, vt
/// [m/s], active = 1 in contact.
template <class T>
struct VertexContact {
  T h, rcx, rcy, lever, vn, vt, active;
};

/// The contact of the vertex at (px, py) [m] of a block centred at (x, y) moving at the half-step
/// velocities, with the ground at height `ground` [m] and unit normal (nx, ny) under it; r [m] is
/// the rounding radius. penetration h = r - (distance of the vertex to the ground); contact point
/// midway in the overlap. kLeverIsArm: a disc on flat ground, whose contact point lies straight
/// below the centre (lever = arm, no square root).
template <bool kLeverIsArm, class T>
inline VertexContact<T> vertex_contact(T px, T py, T x, T y, T vxh, T vyh, T wh, double nx,
                                       double ny, double ground, double r) {
  VertexContact<T> k;
  const T dist = (py - ground) * ny - r;
  k.h = lane_max(-dist, lane_fill<T>(0.0));
  const T arm = r - 0.5 * k.h;  // vertex to contact point, along -n
  k.rcx = px - nx * arm - x;
  k.rcy = py - ny * arm - y;
  const T vcx = vxh - wh * k.rcy;
  const T vcy = vyh + wh * k.rcx;
  k.active = k.h > 0.0 ? lane_fill<T>(1.0) : lane_fill<T>(0.0);
  if constexpr (kLeverIsArm)
    k.lever = arm;
  else
    k.lever = lane_sqrt(k.rcx * k.rcx + k.rcy * k.rcy);
  k.vn = vcx * nx + vcy * ny;
  k.vt = vcx * ny - vcy * nx;
  return k;
}

/// Adds one vertex's contact forces fn, ft [N] and moment mom [N m] to the block's force fx, fy
/// [N] and torque tq [N m], and their work over the step to each stage's tally wn, wt, wr [J]:
/// trapezoidal rule on the force (previous pfn, pft, pmom and current) times the contact point's
/// displacement (half-step velocity times dt), consistent with velocity Verlet's energy update to
/// second order. Each stage writes only its own outputs (effect.hpp), so stage work needs no
/// snapshots. kDiscFlat: the disc on flat ground, n = (0, 1), t = (1, 0), contact point at
/// (0, -l). Also keeps any (a slot in contact) and maxh (the deepest overlap).
template <bool kDiscFlat, class T>
inline void add_contact(T fn, T ft, T mom, const VertexContact<T>& k, double nx, double ny, T wh,
                        double dt, T& fx, T& fy, T& tq, T& wn, T& wt, T& wr, T& pfn, T& pft,
                        T& pmom, T& any, T& maxh) {
  const double half_dt = 0.5 * dt;
  if constexpr (kDiscFlat) {
    fx += ft;
    fy += fn;
    tq += k.lever * ft + mom;
  } else {
    const T fcx = fn * nx + ft * ny;
    const T fcy = fn * ny - ft * nx;
    fx += fcx;
    fy += fcy;
    tq += k.rcx * fcy - k.rcy * fcx + mom;
  }
  wn += (pfn + fn) * k.vn * half_dt;
  wt += (pft + ft) * k.vt * half_dt;
  wr += (pmom + mom) * wh * half_dt;
  pfn = fn;
  pft = ft;
  pmom = mom;
  any = lane_max(any, k.active);
  maxh = lane_max(maxh, k.h);
}

/// Adds a body-stage force fxb, fyb [N] (at the centre of mass) to fx, fy and its work to wb [J],
/// by the same trapezoidal rule.
template <class T>
inline void add_body(T fxb, T fyb, T vxh, T vyh, double dt, T& fx, T& fy, T& wb, T& pfxb, T& pfyb) {
  fx += fxb;
  fy += fyb;
  wb += ((pfxb + fxb) * vxh + (pfyb + fyb) * vyh) * (0.5 * dt);
  pfxb = fxb;
  pfyb = fyb;
}

/// Velocity Verlet's second half from the step's force fx, fy [N] and torque tq [N m], then the
/// contact bookkeeping, branch-free: time t [s], first touch t_first [s], contact phases, had (a
/// contact so far), pending (a predicted re-contact), prev (in contact at the last step) and
/// cand (candidate final separation: no contact, a contact so far, nothing pending and, on flat
/// ground, the centre moving up).
template <bool kFlat, class T>
inline void verlet_second_half(T fx, T fy, T tq, T any, T vxh, T vyh, T wh, double inv_m,
                               double inv_i, double g, double dt, T& ax, T& ay, T& aw, T& vx, T& vy,
                               T& w, T& t, T& t_first, T& phases, T& had, T& pending, T& prev,
                               T& cand) {
  const double half_dt = 0.5 * dt;
  const T zero = lane_fill<T>(0.0), one = lane_fill<T>(1.0);
  ax = fx * inv_m;
  ay = fy * inv_m - g;
  aw = tq * inv_i;
  vx = vxh + ax * half_dt;
  vy = vyh + ay * half_dt;
  w = wh + aw * half_dt;
  t += dt;
  const T onset = any * (1.0 - prev);
  t_first = (had == 0.0) & (any > 0.0) ? t - dt : t_first;
  phases += onset;
  had = lane_max(had, any);
  pending = any > 0.0 ? zero : pending;
  prev = any;
  T leaving = one;
  if constexpr (kFlat) leaving = vy > 0.0 ? one : zero;
  cand = had * (1.0 - any) * leaving * (1.0 - pending);
}

}  // namespace ricochet::detail
