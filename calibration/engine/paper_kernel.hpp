// The engine's fused kernel: every model that holds the paper's law (effects normal + tangential
// + rolling, Garcia et al. 2020 Eq. 3, 5, 6), on flat ground, in one loop whose state stays in
// vector registers. The hot path of calibration, Monte Carlo, Sobol and every diagnosis. Internal
// to the integrator (engine/lane_batch.hpp).
//
// Why: the generic engine streams some ninety lane arrays through memory per step, one loop per
// stage and effect (the price of composing effects at run time), about 80 cycles per collision
// and step on this machine. Here one chunk of kChunk lanes runs step after step in registers
// until one of its collisions needs the driver (a separation, a flight to jump, the time
// limit). The paper's three effects are inlined (their per-lane equations,
// effects/normal.hpp, tangential.hpp, rolling.hpp); any other effect of the model (a candidate,
// a plugin) is called through its own apply() on the chunk, in the model's order, with the
// contact's inputs, factors and forces in small chunk arrays.
//
// Same arithmetic: the integrator and a vertex's contact are the per-lane functions of
// engine/lane_step.hpp, which the generic path (LaneBatch::step and slot_step in engine/lane_batch.hpp)
// calls too, so results are bit for bit those of the generic path (test
// Engine.FusedKernelIsTheGenericPathBitForBit).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstring>

#include "effects/effect.hpp"
#include "effects/normal.hpp"
#include "effects/rolling.hpp"
#include "effects/tangential.hpp"
#include "engine/lane_step.hpp"
#include "engine/vector_math.hpp"

namespace ricochet::detail {

/// Most vertices the fused kernel takes; blocks with more use the generic path.
inline constexpr int kFusedMaxVertices = 4;

/// Most effects in a model, and most parameters or state variables of one effect, that the
/// fused kernel takes; larger models use the generic path.
inline constexpr int kFusedMaxEffects = 8;
inline constexpr int kFusedMaxEffectArrays = 16;

/// One effect of the model, in the model's (stage) order.
struct FusedEffect {
  enum Kind { kNormal, kTangential, kRolling, kOther } kind = kOther;
  const Effect* effect = nullptr;
  const double* params[kFusedMaxEffectArrays] = {};              // lane arrays of its parameters
  double* state[kFusedMaxVertices][kFusedMaxEffectArrays] = {};  // per slot, its state arrays
  int nparams = 0, nstate = 0;
};

/// Pointers into the engine's lane arrays (structure of arrays, lane i at [i]) and the
/// constants of one batch.
struct PaperLanes {
  double *x, *y, *th, *vx, *vy, *w, *ax, *ay, *aw, *t, *t_first, *had, *prev, *phases, *pending,
      *cand, *maxh, *live, *fly_at;
  double *work_normal, *work_tangential, *work_rolling, *work_body;  // work by each stage [J]
  const double *kn, *en2, *kt, *mu, *kr, *muR;
  struct Slot {
    double *h_prev, *pfn, *pft, *pmom, *pfxb, *pfyb;  // overlap and forces of the previous step
    double *fn, *ft, *moment;                         // the paper's effects' per-contact state
  } slot[kFusedMaxVertices];
  double vbx[kFusedMaxVertices], vby[kFusedMaxVertices];  // vertices in the body frame [m]
  double r, dt, g, inv_m, inv_i, max_time, mass, length;
  // Return to the driver when a lane flies (no contact, not leaving, pending == 0) and its
  // next flight check is due (t >= fly_at): the engine advances it ballistically
  // (LaneBatch::fly).
  bool stop_in_flight = false;
  // The model's effects in order (kOther ones are called through apply()).
  FusedEffect effects[kFusedMaxEffects];
  int neffects = 0;
  bool has_coefficient = false, has_body = false;
};

/// cos and sin of each lane, through the engine's one vector loop (vector_math.hpp).
inline void lanes_cos_sin(Lanes th, Lanes& c, Lanes& s) {
  alignas(64) double cb[kChunk], sb[kChunk], tb[kChunk];
  std::memcpy(tb, &th, sizeof tb);
  cos_sin_lanes(tb, cb, sb, kChunk);
  std::memcpy(&c, cb, sizeof c);
  std::memcpy(&s, sb, sizeof s);
}

/// The contact's inputs, factors and forces of one chunk, for effects called through apply().
struct ChunkArrays {
  alignas(64) double active[kChunk], h[kChunk], dh[kChunk], vn[kChunk], vt[kChunk], w[kChunk],
      lever[kChunk], vx[kChunk], vy[kChunk];
  alignas(64) double kf[kChunk], ef[kChunk], enf[kChunk], muf[kChunk], murf[kChunk];
  alignas(64) double fn[kChunk], ft[kChunk], moment[kChunk], fxb[kChunk], fyb[kChunk];
};

/// Steps the kChunk lanes from lane i0 until a live lane reaches final-separation candidacy
/// (cand > 0), the time limit, or (a.stop_in_flight) a flight due for a jump, exactly as
/// LaneBatch::step() would, then stores the state back. kDisc: one vertex at the centre (the
/// paper's cylinder); else NV polygon vertices. kOthers: the model has effects besides the paper's
/// three.
template <bool kDisc, int NV, bool kOthers>
void paper_steps(const PaperLanes& a, std::size_t i0) {
  using T = Lanes;
  using effects::NormalLaw;
  using effects::RollingLaw;
  using effects::TangentialLaw;
  const auto ld = [i0](const double* p) {
    T v;
    std::memcpy(&v, p + i0, sizeof v);
    return v;
  };
  const auto st = [i0](double* p, const T& v) { std::memcpy(p + i0, &v, sizeof v); };
  const auto get = [](const double* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  const auto put = [](double* p, const T& v) { std::memcpy(p, &v, sizeof v); };
  const T zero = lane_fill<T>(0.0), one = lane_fill<T>(1.0);
  T x = ld(a.x), y = ld(a.y), th = ld(a.th), vx = ld(a.vx), vy = ld(a.vy), w = ld(a.w);
  T ax = ld(a.ax), ay = ld(a.ay), aw = ld(a.aw), t = ld(a.t), t_first = ld(a.t_first);
  T had = ld(a.had), prev = ld(a.prev), phases = ld(a.phases), pending = ld(a.pending);
  T cand = ld(a.cand), maxh = ld(a.maxh);
  T wn = ld(a.work_normal), wt = ld(a.work_tangential), wr = ld(a.work_rolling);
  T wb = kOthers ? ld(a.work_body) : zero;
  const T fly_at = a.stop_in_flight ? ld(a.fly_at) : zero;
  const T live = ld(a.live), kn = ld(a.kn), en2 = ld(a.en2), kt = ld(a.kt), mu = ld(a.mu),
          kr = ld(a.kr), muR = ld(a.muR);
  T h_prev[NV], pfn[NV], pft[NV], pmom[NV], pfxb[NV], pfyb[NV], fsn[NV], fst[NV], fsm[NV];
  for (int s = 0; s < NV; ++s) {
    h_prev[s] = ld(a.slot[s].h_prev);
    pfn[s] = ld(a.slot[s].pfn);
    pft[s] = ld(a.slot[s].pft);
    pmom[s] = ld(a.slot[s].pmom);
    pfxb[s] = kOthers ? ld(a.slot[s].pfxb) : zero;
    pfyb[s] = kOthers ? ld(a.slot[s].pfyb) : zero;
    fsn[s] = ld(a.slot[s].fn);
    fst[s] = ld(a.slot[s].ft);
    fsm[s] = ld(a.slot[s].moment);
  }
  ChunkArrays io;
  ContactBatch cb;
  if constexpr (kOthers) {
    cb.n = kChunk;
    cb.dt = a.dt;
    cb.active = io.active, cb.h = io.h, cb.dh = io.dh, cb.vn = io.vn, cb.vt = io.vt, cb.w = io.w;
    cb.lever = io.lever, cb.vx = io.vx, cb.vy = io.vy;
    cb.mass = a.mass, cb.length = a.length;
    cb.kn_factor = io.kf, cb.elastic_factor = io.ef, cb.en2_factor = io.enf;
    cb.mu_factor = io.muf, cb.muR_factor = io.murf;
    cb.fn = io.fn, cb.ft = io.ft, cb.moment = io.moment, cb.fx_body = io.fxb, cb.fy_body = io.fyb;
    // Factors start at 1 and body forces at 0, as the generic path's arrays do.
    for (double* f : {io.kf, io.ef, io.enf, io.muf, io.murf}) put(f, one);
    put(io.fxb, zero), put(io.fyb, zero);
  }
  // An effect outside the paper's three, on this chunk and slot.
  const auto call = [&](const FusedEffect& e, int s) {
    const double* p[kFusedMaxEffectArrays];
    double* q[kFusedMaxEffectArrays];
    for (int k = 0; k < e.nparams; ++k) p[k] = e.params[k] + i0;
    for (int k = 0; k < e.nstate; ++k) q[k] = e.state[s][k] + i0;
    e.effect->apply(cb, p, q);
  };
  const double dt = a.dt;
  const double r = a.r, g = a.g, inv_m = a.inv_m, inv_i = a.inv_i, max_time = a.max_time;
  // Flat ground y = 0: the generic path's constants, so that the compiler folds the same terms.
  const double nx = 0.0, ny = 1.0, ground = 0.0;
  for (;;) {
    T vxh, vyh, wh;
    verlet_first_half(x, y, th, vx, vy, w, ax, ay, aw, dt, vxh, vyh, wh);
    T fx = zero, fy = zero, tq = zero, any = zero;
    T c = zero, sn = zero;
    if constexpr (!kDisc) lanes_cos_sin(th, c, sn);
    for (int s = 0; s < NV; ++s) {
      T px, py;
      if constexpr (kDisc) {
        px = x;
        py = y;
      } else {
        px = x + c * a.vbx[s] - sn * a.vby[s];
        py = y + sn * a.vbx[s] + c * a.vby[s];
      }
      const VertexContact<T> k =
          vertex_contact<kDisc>(px, py, x, y, vxh, vyh, wh, nx, ny, ground, r);
      const T h = k.h, active = k.active, lever = k.lever, vn = k.vn, vt = k.vt;
      const T dh = h - h_prev[s];
      h_prev[s] = h;
      T fn = zero, ft = zero, mom = zero, fxb = zero, fyb = zero;
      if constexpr (!kOthers) {
        fsn[s] = NormalLaw::force(fsn[s], kn, en2, dh, h, active, one, one, one);
        fn += fsn[s];
        fst[s] = TangentialLaw::force(fst[s], kt, mu, vt, fn, active, one, dt);
        ft += fst[s];
        fsm[s] = RollingLaw::moment(fsm[s], kr, muR, wh, lever, fn, active, one, dt);
        mom += fsm[s];
      } else {
        put(io.active, active), put(io.h, h), put(io.dh, dh), put(io.vn, vn), put(io.vt, vt);
        put(io.w, wh), put(io.lever, lever), put(io.vx, vxh), put(io.vy, vyh);
        if (a.has_coefficient)
          for (double* f : {io.kf, io.ef, io.enf, io.muf, io.murf}) put(f, one);
        if (a.has_body) put(io.fxb, zero), put(io.fyb, zero);
        put(io.fn, zero), put(io.ft, zero), put(io.moment, zero);
        for (int e = 0; e < a.neffects; ++e) {
          const FusedEffect& eff = a.effects[e];
          switch (eff.kind) {
            case FusedEffect::kNormal:
              fn = get(io.fn);
              fsn[s] = NormalLaw::force(fsn[s], kn, en2, dh, h, active, get(io.kf), get(io.ef),
                                        get(io.enf));
              put(io.fn, fn + fsn[s]);
              break;
            case FusedEffect::kTangential:
              fst[s] =
                  TangentialLaw::force(fst[s], kt, mu, vt, get(io.fn), active, get(io.muf), dt);
              put(io.ft, get(io.ft) + fst[s]);
              break;
            case FusedEffect::kRolling:
              fsm[s] = RollingLaw::moment(fsm[s], kr, muR, wh, lever, get(io.fn), active,
                                          get(io.murf), dt);
              put(io.moment, get(io.moment) + fsm[s]);
              break;
            case FusedEffect::kOther:
              call(eff, s);
              break;
          }
        }
        // History is cleared when the contact is lost (whatever the effect did).
        for (int e = 0; e < a.neffects; ++e) {
          const FusedEffect& eff = a.effects[e];
          if (eff.kind != FusedEffect::kOther) continue;
          for (int j = 0; j < eff.nstate; ++j) {
            double* q = eff.state[s][j] + i0;
            put(q, active > 0.0 ? get(q) : zero);
          }
        }
        fn = get(io.fn), ft = get(io.ft), mom = get(io.moment);
        if (a.has_body) fxb = get(io.fxb), fyb = get(io.fyb);
      }
      add_contact<kDisc>(fn, ft, mom, k, nx, ny, wh, dt, fx, fy, tq, wn, wt, wr, pfn[s], pft[s],
                         pmom[s], any, maxh);
      if constexpr (kOthers)
        if (a.has_body) add_body(fxb, fyb, vxh, vyh, dt, fx, fy, wb, pfxb[s], pfyb[s]);
    }
    verlet_second_half<true>(fx, fy, tq, any, vxh, vyh, wh, inv_m, inv_i, g, dt, ax, ay, aw, vx, vy,
                             w, t, t_first, phases, had, pending, prev, cand);
    auto stop = (live > 0.0) & ((cand > 0.0) | (t >= max_time));
    if constexpr (!kDisc)
      if (a.stop_in_flight) stop |= (live > 0.0) & (any == 0.0) & (pending == 0.0) & (t >= fly_at);
    long stopped = 0;
    for (std::size_t k = 0; k < kChunk; ++k) stopped |= stop[k];
    if (stopped) break;
  }
  st(a.x, x), st(a.y, y), st(a.th, th), st(a.vx, vx), st(a.vy, vy), st(a.w, w);
  st(a.ax, ax), st(a.ay, ay), st(a.aw, aw), st(a.t, t), st(a.t_first, t_first);
  st(a.had, had), st(a.prev, prev), st(a.phases, phases), st(a.pending, pending);
  st(a.cand, cand), st(a.maxh, maxh);
  st(a.work_normal, wn), st(a.work_tangential, wt), st(a.work_rolling, wr);
  if constexpr (kOthers) st(a.work_body, wb);
  for (int s = 0; s < NV; ++s) {
    st(a.slot[s].h_prev, h_prev[s]);
    st(a.slot[s].pfn, pfn[s]);
    st(a.slot[s].pft, pft[s]);
    st(a.slot[s].pmom, pmom[s]);
    if constexpr (kOthers) st(a.slot[s].pfxb, pfxb[s]), st(a.slot[s].pfyb, pfyb[s]);
    st(a.slot[s].fn, fsn[s]);
    st(a.slot[s].ft, fst[s]);
    st(a.slot[s].moment, fsm[s]);
  }
}

}  // namespace ricochet::detail
