// The engine's integrator (engine.cpp's only): the lane layout of a model's parameters and
// states, and LaneBatch, which integrates up to `lanes` collisions side by side (structure of
// arrays). Internal: included by engine.cpp alone; the public API is engine/engine.hpp.
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"
#include "engine/engine.hpp"
#include "engine/lane_step.hpp"
#include "engine/paper_kernel.hpp"
#include "engine/vector_math.hpp"

namespace ricochet::engine_internal {

// Where each effect's parameters and state variables live in the lane arrays.
struct Layout {
  std::vector<const Effect*> effects;
  std::vector<std::size_t> param_offset, state_offset, state_count;
  std::size_t params = 0, states = 0;

  explicit Layout(const Model& model) {
    for (std::size_t e = 0; e < model.effects().size(); ++e) {
      const Effect* eff = model.effects()[e];
      effects.push_back(eff);
      param_offset.push_back(model.offset(e));
      state_offset.push_back(states);
      state_count.push_back(eff->state().size());
      states += eff->state().size();
    }
    params = model.parameter_count();
  }
};

// Integrates up to `lanes` collisions side by side (structure of arrays), refilling a lane from
// the case queue as soon as its rebound ends. All buffers are allocated once, in the
// constructor: the step loop never allocates. kDisc / kFlat select the cheap geometry of a disc
// on flat ground (no rotation, constant normal), the paper's cylinder case.
template <bool kDisc, bool kFlat>
class LaneBatch {
 public:
  LaneBatch(const Layout& layout, const Shape& shape, const EngineOptions& options,
            std::span<const CollisionCase> cases, std::span<const double> params, bool broadcast,
            CollisionResult* results, Trace* trace)
      : layout_(layout),
        shape_(shape),
        opt_(options),
        cases_(cases),
        params_(params),
        broadcast_(broadcast),
        results_(results),
        trace_(trace),
        L_(padded(std::min(options.lanes, cases.size()))),
        W_(L_),
        V_(shape.vertices.size()),
        buffer_(L_ * (kLaneArrays + kStages + V_ * kSlotArrays + kFactorArrays + layout.params +
                      layout.states * V_),
                0.0),
        case_of_(L_, -1) {
    double* p = buffer_.data();
    auto take = [&](double*& a) {
      a = p;
      p += L_;
    };
    for (double** a :
         {&x_,    &y_,      &th_,   &vx_,      &vy_,   &w_,     &ax_,      &ay_,  &aw_,   &vxh_,
          &vyh_,  &wh_,     &fx_,   &fy_,      &tq_,   &t_,     &t_first_, &had_, &any_,  &prev_,
          &maxh_, &phases_, &cand_, &pending_, &y_in_, &ke_in_, &cth_,     &sth_, &live_, &fly_at_})
      take(*a);
    for (auto& a : work_) take(a);
    slot_.resize(V_);
    for (auto& s : slot_)
      for (double** a :
           {&s.h_prev, &s.active, &s.h,    &s.dh,   &s.vn,   &s.vt,   &s.lever,    &s.rcx,
            &s.rcy,    &s.nx,     &s.ny,   &s.fn,   &s.ft,   &s.mom,  &s.fxb,      &s.fyb,
            &s.pfn,    &s.pft,    &s.pmom, &s.pfxb, &s.pfyb, &s.lift, &s.lift_next})
        take(*a);
    for (double** a : {&kf_, &ef_, &enf_, &muf_, &murf_}) take(*a);
    param_.resize(layout.params);
    for (auto& a : param_) take(a);
    state_.resize(layout.states * V_);
    for (auto& a : state_) take(a);
    // Pointer tables handed to the effects, built once.
    eparams_.resize(layout.effects.size());
    estate_.resize(layout.effects.size() * V_);
    for (std::size_t e = 0; e < layout.effects.size(); ++e) {
      const auto np = layout.effects[e]->parameters().size();
      for (std::size_t k = 0; k < np; ++k)
        eparams_[e].push_back(param_[layout.param_offset[e] + k]);
      for (std::size_t s = 0; s < V_; ++s)
        for (std::size_t j = 0; j < layout.state_count[e]; ++j)
          estate_[e * V_ + s].push_back(state_[(layout.state_offset[e] + j) * V_ + s]);
    }
    for (const Effect* e : layout.effects) {
      has_body_ = has_body_ || e->stage() == Stage::kBody;
      has_coefficient_ = has_coefficient_ || e->stage() == Stage::kCoefficient;
      has_lift_ = has_lift_ || e->moves_surface();
    }
    for (double* f : {kf_, ef_, enf_, muf_, murf_}) std::fill_n(f, L_, 1.0);
    dt_ = options.dt_s;
    g_ = options.gravity_mps2;
    r_ = shape.rounding_radius_m;
    inv_m_ = 1.0 / shape.mass_kg;
    inv_i_ = 1.0 / shape.inertia_kgm2;
    if constexpr (kFlat) set_up_fused();
  }

  void run() {
    std::size_t busy = 0;
    for (std::size_t i = 0; i < L_; ++i) {
      load(i);
      if (case_of_[i] >= 0) ++busy;
    }
    if (trace_) record();
    while (busy > 0) {
      if (fused_)
        for (std::size_t i0 = 0; i0 < W_; i0 += kVector) fused_(paper_, i0);
      else
        step();
      if (trace_) record();
      for (std::size_t i = 0; i < W_; ++i) {
        if (case_of_[i] < 0) continue;
        if (cand_[i] > 0.0 || t_[i] >= opt_.max_time_s) {
          if (finish_if_over(i)) {
            load(i);
            if (case_of_[i] < 0) --busy;
          }
        } else if (kFlightSkip && prev_[i] == 0.0 && pending_[i] == 0.0 && t_[i] >= fly_at_[i]) {
          fly(i);
        }
      }
      // Once the queue is empty, lanes only finish: without compaction the last, longest
      // collisions of a batch are integrated at the full width, mostly idle lanes (compaction
      // took 13 % off the lab-triangle diagnosis's CPU). Traces read lane 0: never moved.
      if (next_ >= cases_.size() && !trace_ && busy + kVector <= W_) compact(busy);
    }
  }

 private:
  // Lanes come in whole vectors (8 doubles = AVX-512), idle ones padding: every lane then takes
  // the vectorised path, whose cos/sin (libmvec) may differ in the last bit from the scalar
  // remainder loop's, so a collision's result does not depend on its lane or the batch size.
  static constexpr std::size_t kVector = detail::kChunk;
  static std::size_t padded(std::size_t lanes) {
    return (std::max<std::size_t>(1, lanes) + kVector - 1) / kVector * kVector;
  }

  static constexpr std::size_t kLaneArrays = 30;
  static constexpr std::size_t kStages = kStageCount;
  static constexpr std::size_t kSlotArrays = 23;
  static constexpr std::size_t kFactorArrays = 5;

  struct Slot {
    double *h_prev, *active, *h, *dh, *vn, *vt, *lever, *rcx, *rcy, *nx, *ny;
    double *fn, *ft, *mom, *fxb, *fyb;
    double *pfn, *pft, *pmom, *pfxb, *pfyb;  // forces of the previous step (work accounting)
    double *lift, *lift_next;                // the surface under the slot (ContactBatch::lift) [m]
  };

  // Models that hold the paper's law (normal, tangential, rolling), on flat ground, without a
  // trace, an effect that moves the surface or sizes beyond the kernel's fixed ones run in the
  // fused kernel (engine/paper_kernel.hpp); anything else steps here.
  void set_up_fused() {
    using detail::FusedEffect;
    if (trace_ || has_lift_ || V_ > detail::kFusedMaxVertices ||
        layout_.effects.size() > detail::kFusedMaxEffects)
      return;
    detail::PaperLanes& a = paper_;
    a.x = x_, a.y = y_, a.th = th_, a.vx = vx_, a.vy = vy_, a.w = w_, a.ax = ax_, a.ay = ay_;
    a.aw = aw_, a.t = t_, a.t_first = t_first_, a.had = had_, a.prev = prev_, a.phases = phases_;
    a.pending = pending_, a.cand = cand_, a.maxh = maxh_, a.live = live_, a.fly_at = fly_at_;
    a.work_normal = work_[static_cast<int>(Stage::kNormal)];
    a.work_tangential = work_[static_cast<int>(Stage::kTangential)];
    a.work_rolling = work_[static_cast<int>(Stage::kRolling)];
    a.work_body = work_[static_cast<int>(Stage::kBody)];
    int found[3] = {0, 0, 0};
    for (std::size_t e = 0; e < layout_.effects.size(); ++e) {
      const Effect& eff = *layout_.effects[e];
      FusedEffect& f = a.effects[e];
      f.effect = &eff;
      const FusedLaw law = eff.fused_law();
      f.kind = law == FusedLaw::kPaperNormal       ? FusedEffect::kNormal
               : law == FusedLaw::kPaperTangential ? FusedEffect::kTangential
               : law == FusedLaw::kPaperRolling    ? FusedEffect::kRolling
                                                   : FusedEffect::kOther;
      f.nparams = static_cast<int>(eparams_[e].size());
      f.nstate = static_cast<int>(layout_.state_count[e]);
      if (f.nparams > detail::kFusedMaxEffectArrays || f.nstate > detail::kFusedMaxEffectArrays)
        return;
      for (int k = 0; k < f.nparams; ++k) f.params[k] = eparams_[e][k];
      for (std::size_t s = 0; s < V_; ++s)
        for (int k = 0; k < f.nstate; ++k) f.state[s][k] = estate_[e * V_ + s][k];
      if (f.kind == FusedEffect::kOther) continue;
      ++found[f.kind];
      // The law's two parameters by their declared roles (the registry checked that each
      // appears once).
      const std::array<ParameterRole, 2> roles = fused_law_roles(law);
      const double* p[2] = {nullptr, nullptr};
      const auto specs = eff.parameters();
      for (std::size_t k = 0; k < specs.size(); ++k)
        for (int r = 0; r < 2; ++r)
          if (specs[k].role == roles[r]) p[r] = eparams_[e][k];
      if (!p[0] || !p[1]) return;
      if (f.kind == FusedEffect::kNormal) a.kn = p[0], a.en2 = p[1];
      if (f.kind == FusedEffect::kTangential) a.kt = p[0], a.mu = p[1];
      if (f.kind == FusedEffect::kRolling) a.kr = p[0], a.muR = p[1];
      for (std::size_t s = 0; s < V_; ++s) {
        double* state = estate_[e * V_ + s][0];
        (f.kind == FusedEffect::kNormal       ? a.slot[s].fn
         : f.kind == FusedEffect::kTangential ? a.slot[s].ft
                                              : a.slot[s].moment) = state;
      }
    }
    if (found[0] != 1 || found[1] != 1 || found[2] != 1) return;
    a.neffects = static_cast<int>(layout_.effects.size());
    a.has_coefficient = has_coefficient_;
    a.has_body = has_body_;
    for (std::size_t s = 0; s < V_; ++s) {
      const Slot& sl = slot_[s];
      a.slot[s].h_prev = sl.h_prev, a.slot[s].pfn = sl.pfn, a.slot[s].pft = sl.pft;
      a.slot[s].pmom = sl.pmom, a.slot[s].pfxb = sl.pfxb, a.slot[s].pfyb = sl.pfyb;
      a.vbx[s] = shape_.vertices[s][0];
      a.vby[s] = shape_.vertices[s][1];
    }
    a.r = r_, a.dt = dt_, a.g = g_, a.inv_m = inv_m_, a.inv_i = inv_i_;
    a.stop_in_flight = kFlightSkip && opt_.skip_flights;
    a.max_time = opt_.max_time_s;
    a.mass = shape_.mass_kg, a.length = shape_.length_m;
    fused_ = pick_kernel(a.neffects > 3, V_);
  }

  // The kernel instance for this block's shape (its vertex count) and model.
  using Kernel = void (*)(const detail::PaperLanes&, std::size_t);
  static Kernel pick_kernel(bool others, std::size_t vertices) {
    if constexpr (kDisc) {
      return others ? detail::paper_steps<true, 1, true> : detail::paper_steps<true, 1, false>;
    } else {
      static constexpr Kernel kLean[] = {
          nullptr, detail::paper_steps<false, 1, false>, detail::paper_steps<false, 2, false>,
          detail::paper_steps<false, 3, false>, detail::paper_steps<false, 4, false>};
      static constexpr Kernel kFull[] = {
          nullptr, detail::paper_steps<false, 1, true>, detail::paper_steps<false, 2, true>,
          detail::paper_steps<false, 3, true>, detail::paper_steps<false, 4, true>};
      return others ? kFull[vertices] : kLean[vertices];
    }
  }

  void load(std::size_t i) {
    if (next_ >= cases_.size()) {
      case_of_[i] = -1;
      // An idle lane far above the ground: it never touches and costs nothing to integrate.
      y_[i] = 1e9;
      live_[i] = 0.0;
      vx_[i] = vy_[i] = w_[i] = ax_[i] = ay_[i] = aw_[i] = 0.0;
      cand_[i] = 0.0;
      return;
    }
    const std::size_t k = next_++;
    case_of_[i] = static_cast<long>(k);
    live_[i] = 1.0;
    const CollisionCase& c = cases_[k];
    double ground = 0, nx = 0, ny = 1;
    if (!kFlat) opt_.ground.surface(0.0, ground, nx, ny);
    x_[i] = 0.0;
    th_[i] = c.alpha_rad;
    y_[i] = ground + shape_.depth_below_centroid(c.alpha_rad) + opt_.initial_gap_m;
    vx_[i] = c.vin[kVx];
    vy_[i] = c.vin[kVy];
    w_[i] = c.vin[kW];
    ax_[i] = 0.0;
    ay_[i] = -g_;
    aw_[i] = 0.0;
    t_[i] = t_first_[i] = had_[i] = any_[i] = prev_[i] = maxh_[i] = phases_[i] = 0.0;
    cand_[i] = pending_[i] = fly_at_[i] = 0.0;
    for (auto& w : work_) w[i] = 0.0;
    y_in_[i] = y_[i];
    ke_in_[i] = kinetic(i);
    for (auto& s : slot_)
      s.h_prev[i] = s.pfn[i] = s.pft[i] = s.pmom[i] = s.pfxb[i] = s.pfyb[i] = s.lift[i] =
          s.lift_next[i] = 0.0;
    for (auto& s : state_) s[i] = 0.0;
    const double* row = broadcast_ ? params_.data() : params_.data() + k * layout_.params;
    for (std::size_t q = 0; q < layout_.params; ++q) param_[q][i] = row[q];
  }

  // Moves the live lanes to the front, in order, and narrows the integrated width to the
  // vectors they fill. A lane's state is one column of buffer_ (every array has stride L_), so
  // the move is exact and a collision's result does not depend on it (Engine tests).
  void compact(std::size_t busy) {
    const std::size_t arrays = buffer_.size() / L_;
    std::size_t j = 0;
    for (std::size_t i = 0; i < W_; ++i) {
      if (case_of_[i] < 0) continue;
      if (i != j) {
        for (std::size_t a = 0; a < arrays; ++a) buffer_[a * L_ + j] = buffer_[a * L_ + i];
        case_of_[j] = case_of_[i];
      }
      ++j;
    }
    W_ = padded(busy);
    for (std::size_t i = j; i < W_; ++i) load(i);  // the queue is empty: idle padding lanes
  }

  double kinetic(std::size_t i) const {
    return 0.5 * shape_.mass_kg * (vx_[i] * vx_[i] + vy_[i] * vy_[i]) +
           0.5 * shape_.inertia_kgm2 * w_[i] * w_[i];
  }

  // One velocity-Verlet step for all lanes. Local __restrict copies of the array pointers let
  // the compiler vectorise: stores through one array cannot move the others.
  void step() {
    const std::size_t n = W_;
    const double dt = dt_;
    const double inv_m = inv_m_, inv_i = inv_i_, g = g_;
    double* __restrict x = x_;
    double* __restrict y = y_;
    double* __restrict th = th_;
    double* __restrict vx = vx_;
    double* __restrict vy = vy_;
    double* __restrict w = w_;
    double* __restrict ax = ax_;
    double* __restrict ay = ay_;
    double* __restrict aw = aw_;
    double* __restrict vxh = vxh_;
    double* __restrict vyh = vyh_;
    double* __restrict wh = wh_;
    double* __restrict fx = fx_;
    double* __restrict fy = fy_;
    double* __restrict tq = tq_;
    double* __restrict any = any_;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < n; ++i) {
      detail::verlet_first_half(x[i], y[i], th[i], vx[i], vy[i], w[i], ax[i], ay[i], aw[i], dt,
                                vxh[i], vyh[i], wh[i]);
      fx[i] = 0.0;
      fy[i] = 0.0;
      tq[i] = 0.0;
      any[i] = 0.0;
    }
    if (!kDisc) detail::cos_sin_lanes(th, cth_, sth_, n);
    for (std::size_t s = 0; s < V_; ++s) slot_step(s);
    double* __restrict t = t_;
    double* __restrict t_first = t_first_;
    double* __restrict had = had_;
    double* __restrict prev = prev_;
    double* __restrict phases = phases_;
    double* __restrict pending = pending_;
    double* __restrict cand = cand_;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < n; ++i)
      detail::verlet_second_half<kFlat>(fx[i], fy[i], tq[i], any[i], vxh[i], vyh[i], wh[i], inv_m,
                                        inv_i, g, dt, ax[i], ay[i], aw[i], vx[i], vy[i], w[i], t[i],
                                        t_first[i], phases[i], had[i], pending[i], prev[i],
                                        cand[i]);
  }

  void slot_step(std::size_t s) {
    Slot& sl = slot_[s];
    const std::size_t n = W_;
    const double r = r_;
    const double vbx = shape_.vertices[s][0], vby = shape_.vertices[s][1];
    const double* __restrict x = x_;
    const double* __restrict y = y_;
    const double* __restrict c = cth_;
    const double* __restrict sn = sth_;
    const double* __restrict vxh = vxh_;
    const double* __restrict vyh = vyh_;
    const double* __restrict wh = wh_;
    double* __restrict active = sl.active;
    double* __restrict hh = sl.h;
    double* __restrict dh = sl.dh;
    double* __restrict h_prev = sl.h_prev;
    double* __restrict rcx_a = sl.rcx;
    double* __restrict rcy_a = sl.rcy;
    double* __restrict nx_a = sl.nx;
    double* __restrict ny_a = sl.ny;
    double* __restrict lever = sl.lever;
    double* __restrict vn = sl.vn;
    double* __restrict vt = sl.vt;
    double* __restrict fn = sl.fn;
    double* __restrict ft = sl.ft;
    double* __restrict mom = sl.mom;
    double* __restrict fxb = sl.fxb;
    double* __restrict fyb = sl.fyb;
    double* __restrict kf = kf_;
    double* __restrict ef = ef_;
    double* __restrict enf = enf_;
    double* __restrict muf = muf_;
    double* __restrict murf = murf_;
    const bool lifts = has_lift_;
    double* __restrict lift = sl.lift;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < n; ++i) {
      double px, py, nx = 0.0, ny = 1.0, ground = 0.0;
      if (kDisc) {
        px = x[i];
        py = y[i];
      } else {
        px = x[i] + c[i] * vbx - sn[i] * vby;
        py = y[i] + sn[i] * vbx + c[i] * vby;
      }
      if (!kFlat) opt_.ground.surface(px, ground, nx, ny);
      if (lifts) ground += lift[i];  // the surface an effect has moved (moves_surface)
      const auto k = detail::vertex_contact < kDisc &&
                     kFlat > (px, py, x[i], y[i], vxh[i], vyh[i], wh[i], nx, ny, ground, r);
      active[i] = k.active;
      hh[i] = k.h;
      dh[i] = k.h - h_prev[i];
      h_prev[i] = k.h;
      if (!(kDisc && kFlat)) {  // a disc on flat ground: contact point straight below
        rcx_a[i] = k.rcx;
        rcy_a[i] = k.rcy;
        nx_a[i] = nx;
        ny_a[i] = ny;
      }
      lever[i] = k.lever;
      vn[i] = k.vn;
      vt[i] = k.vt;
      fn[i] = 0.0;
      ft[i] = 0.0;
      mom[i] = 0.0;
    }
    // Factors and body forces are reset only for models that write them (they start at 1 and
    // 0): seven fewer arrays streamed per slot and step for the paper's law.
    if (has_coefficient_) {
      RICOCHET_SIMD
      for (std::size_t i = 0; i < n; ++i) {
        kf[i] = 1.0;
        ef[i] = 1.0;
        enf[i] = 1.0;
        muf[i] = 1.0;
        murf[i] = 1.0;
      }
    }
    if (has_body_) {
      RICOCHET_SIMD
      for (std::size_t i = 0; i < n; ++i) {
        fxb[i] = 0.0;
        fyb[i] = 0.0;
      }
    }
    ContactBatch cb;
    cb.n = n;
    cb.dt = dt_;
    cb.active = sl.active;
    cb.h = sl.h;
    cb.dh = sl.dh;
    cb.vn = sl.vn;
    cb.vt = sl.vt;
    cb.w = wh_;
    cb.lever = sl.lever;
    cb.vx = vxh_;
    cb.vy = vyh_;
    cb.mass = shape_.mass_kg;
    cb.length = shape_.length_m;
    cb.kn_factor = kf_;
    cb.elastic_factor = ef_;
    cb.en2_factor = enf_;
    cb.mu_factor = muf_;
    cb.muR_factor = murf_;
    cb.fn = sl.fn;
    cb.ft = sl.ft;
    cb.moment = sl.mom;
    cb.fx_body = sl.fxb;
    cb.fy_body = sl.fyb;
    if (has_lift_) {
      std::copy_n(sl.lift, n, sl.lift_next);
      cb.lift = sl.lift;
      cb.lift_next = sl.lift_next;
    }
    for (std::size_t e = 0; e < layout_.effects.size(); ++e)
      layout_.effects[e]->apply(cb, eparams_[e].data(), estate_[e * V_ + s].data());
    // History is cleared when the contact is lost (whatever the effect did).
    for (std::size_t e = 0; e < layout_.effects.size(); ++e)
      for (double* st_ptr : estate_[e * V_ + s]) {
        double* __restrict st = st_ptr;
        RICOCHET_SIMD
        for (std::size_t i = 0; i < n; ++i) st[i] = active[i] > 0.0 ? st[i] : 0.0;
      }
    double* __restrict fx = fx_;
    double* __restrict fy = fy_;
    double* __restrict tq = tq_;
    double* __restrict any = any_;
    double* __restrict maxh = maxh_;
    double* __restrict wn = work_[static_cast<int>(Stage::kNormal)];
    double* __restrict wt = work_[static_cast<int>(Stage::kTangential)];
    double* __restrict wr = work_[static_cast<int>(Stage::kRolling)];
    double* __restrict wb = work_[static_cast<int>(Stage::kBody)];
    double* __restrict pfn = sl.pfn;
    double* __restrict pft = sl.pft;
    double* __restrict pmom = sl.pmom;
    double* __restrict pfxb = sl.pfxb;
    double* __restrict pfyb = sl.pfyb;
    // The disc on flat ground (the paper's cylinder) streams fewer arrays in the hottest loop:
    // n = (0, 1) and the contact point straight below (lane_step.hpp, add_contact).
    constexpr bool kDiscFlat = kDisc && kFlat;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < n; ++i) {
      // The penetration kept (maxh) is the depth below the undisturbed ground.
      const detail::VertexContact<double> k{lifts ? hh[i] - lift[i] : hh[i],
                                            kDiscFlat ? 0.0 : rcx_a[i],
                                            kDiscFlat ? 0.0 : rcy_a[i],
                                            lever[i],
                                            vn[i],
                                            vt[i],
                                            active[i]};
      detail::add_contact<kDiscFlat>(fn[i], ft[i], mom[i], k, kDiscFlat ? 0.0 : nx_a[i],
                                     kDiscFlat ? 1.0 : ny_a[i], wh[i], dt_, fx[i], fy[i], tq[i],
                                     wn[i], wt[i], wr[i], pfn[i], pft[i], pmom[i], any[i], maxh[i]);
    }
    if (has_body_) {  // only models with a body-stage effect (ploughing) have body forces
      RICOCHET_SIMD
      for (std::size_t i = 0; i < n; ++i)
        detail::add_body(fxb[i], fyb[i], vxh[i], vyh[i], dt_, fx[i], fy[i], wb[i], pfxb[i],
                         pfyb[i]);
    }
    if (lifts) {  // the moved surface holds while the contact does
      const double* __restrict next = sl.lift_next;
      RICOCHET_SIMD
      for (std::size_t i = 0; i < n; ++i) lift[i] = active[i] > 0.0 ? next[i] : 0.0;
    }
  }

  // A polygon on flat ground out of contact and not leaving (a hop between contact phases, or
  // the fall before the first contact) flies ballistically: stepping through those flights was
  // a third of a lab triangle's steps. fly() jumps it by whole steps while no vertex can reach
  // the ground, then lets it step on until fly_at_.
  static constexpr bool kFlightSkip = !kDisc && kFlat;

  // Conservative advancement (as in continuous collision detection). Out of contact the forces
  // are zero, so each vertex's height is p(tau) = y + vy tau - g tau^2 / 2 + R sin(theta + w tau
  // + phi), whose second derivative is at least -(g + R w^2): p(tau) >= p0 + p0' tau - (g +
  // R w^2) tau^2 / 2, and no vertex touches before the first root of that bound. The lane jumps
  // by the whole steps before it, with the exact ballistic solution, which is what velocity
  // Verlet computes for constant acceleration: the step grid and the result stay those of
  // stepping, up to rounding. Repeated while a jump saves at least kMinJump steps; the next check
  // is kRecheck steps later (fly_at_).
  void fly(std::size_t i) {
    constexpr long kMinJump = 8, kRecheck = 32;
    const double dt = dt_;
    for (int round = 0; round < 16; ++round) {
      const double c = std::cos(th_[i]), s = std::sin(th_[i]), w = w_[i];
      double tau = INFINITY;
      for (const auto& v : shape_.vertices) {
        const double height = y_[i] + s * v[0] + c * v[1] - r_;  // clearance of this vertex
        const double rate = vy_[i] + w * (c * v[0] - s * v[1]);
        const double curve = g_ + w * w * std::hypot(v[0], v[1]);
        tau = std::min(
            tau, (rate + std::sqrt(rate * rate + 2.0 * curve * std::max(height, 0.0))) / curve);
      }
      const long left = static_cast<long>((opt_.max_time_s - t_[i]) / dt) - 1;
      const long n = std::min(static_cast<long>(tau / dt) - 1, left);
      if (n < kMinJump) break;
      const double jump = static_cast<double>(n) * dt;
      x_[i] += vx_[i] * jump;
      y_[i] += vy_[i] * jump - 0.5 * g_ * jump * jump;
      th_[i] += w * jump;
      vy_[i] -= g_ * jump;
      t_[i] += jump;
    }
    fly_at_[i] = t_[i] + kRecheck * dt;
  }

  // Lowest clearance of the block above the ground after a ballistic flight of tau seconds.
  double clearance_after(std::size_t i, double tau) const {
    const double xc = x_[i] + vx_[i] * tau;
    const double yc = y_[i] + vy_[i] * tau - 0.5 * g_ * tau * tau;
    const double th = th_[i] + w_[i] * tau;
    const double c = std::cos(th), s = std::sin(th);
    double lowest = 1e300;
    for (const auto& v : shape_.vertices) {
      const double px = xc + c * v[0] - s * v[1];
      const double py = yc + s * v[0] + c * v[1];
      double ground = 0, nx = 0, ny = 1;
      if (!kFlat) opt_.ground.surface(px, ground, nx, ny);
      lowest = std::min(lowest, (py - ground) * ny - r_);
    }
    return lowest;
  }

  // Decides whether lane i's rebound is over; if so writes its result and returns true.
  bool finish_if_over(std::size_t i) {
    const bool timeout = t_[i] >= opt_.max_time_s;
    if (!timeout && !(kDisc && kFlat)) {
      // Will a vertex swing back onto the ground before the apex? Then the rebound goes on.
      const double horizon = std::max(vy_[i], 0.0) / g_ + (kFlat ? 0.0 : 0.02);
      const double turn = std::fabs(w_[i]) * horizon;
      const int samples = std::clamp(static_cast<int>(std::ceil(turn / (M_PI / 90.0))), 20, 4000);
      for (int k = 1; k <= samples; ++k) {
        const double tau = horizon * k / samples;
        if (clearance_after(i, tau) <= 0.0) {
          const double jump = horizon * (k - 1) / samples;
          x_[i] += vx_[i] * jump;
          y_[i] += vy_[i] * jump - 0.5 * g_ * jump * jump;
          th_[i] += w_[i] * jump;
          vy_[i] -= g_ * jump;
          t_[i] += jump;
          ax_[i] = aw_[i] = 0.0;
          ay_[i] = -g_;
          pending_[i] = 1.0;
          cand_[i] = 0.0;
          return false;
        }
      }
    }
    CollisionResult& res = results_[case_of_[i]];
    res.vout = {vx_[i], vy_[i], w_[i]};
    res.status = timeout
                     ? (had_[i] > 0.0 ? CollisionStatus::kNoRebound : CollisionStatus::kNoContact)
                     : CollisionStatus::kOk;
    res.contact_duration_s = had_[i] > 0.0 ? t_[i] - t_first_[i] : 0.0;
    res.max_penetration_m = maxh_[i];
    res.contact_phases = static_cast<int>(phases_[i]);
    res.end_time_s = t_[i];
    res.alpha_out_rad = th_[i];
    for (std::size_t s = 0; s < kStageCount; ++s) res.dissipated_J[s] = 0.0 - work_[s][i];
    res.kinetic_in_J = ke_in_[i];
    res.kinetic_out_J = kinetic(i);
    res.potential_change_J = shape_.mass_kg * g_ * (y_[i] - y_in_[i]);
    return true;
  }

  void record() {
    Trace& tr = *trace_;
    tr.t.push_back(t_[0]);
    tr.x.push_back(x_[0]);
    tr.y.push_back(y_[0]);
    tr.theta.push_back(th_[0]);
    tr.vx.push_back(vx_[0]);
    tr.vy.push_back(vy_[0]);
    tr.w.push_back(w_[0]);
    double fn = 0, ft = 0, mom = 0, h = 0;
    for (const auto& s : slot_) {
      fn += s.fn[0];
      ft += s.ft[0];
      mom += s.mom[0];
      h = std::max(h, s.h[0]);
    }
    tr.fn.push_back(fn);
    tr.ft.push_back(ft);
    tr.moment.push_back(mom);
    tr.h.push_back(h);
  }

  const Layout& layout_;
  const Shape& shape_;
  const EngineOptions& opt_;
  std::span<const CollisionCase> cases_;
  std::span<const double> params_;
  bool broadcast_;
  CollisionResult* results_;
  Trace* trace_;
  std::size_t L_;  // lanes allocated
  std::size_t W_;  // lanes integrated: L_, narrowed by compact() when the queue is empty
  std::size_t V_;
  std::vector<double> buffer_;
  std::vector<long> case_of_;
  std::size_t next_ = 0;
  double dt_, g_, r_, inv_m_, inv_i_;
  bool has_body_ = false, has_coefficient_ = false, has_lift_ = false;

  double *x_, *y_, *th_, *vx_, *vy_, *w_, *ax_, *ay_, *aw_, *vxh_, *vyh_, *wh_;
  double *fx_, *fy_, *tq_, *t_, *t_first_, *had_, *any_, *prev_, *maxh_, *phases_;
  double *cand_, *pending_, *y_in_, *ke_in_, *cth_, *sth_, *live_, *fly_at_;
  detail::PaperLanes paper_{};
  Kernel fused_ = nullptr;
  std::array<double*, kStageCount> work_{};
  std::vector<Slot> slot_;
  double *kf_, *ef_, *enf_, *muf_, *murf_;
  std::vector<double*> param_, state_;
  std::vector<std::vector<const double*>> eparams_;
  std::vector<std::vector<double*>> estate_;
};

}  // namespace ricochet::engine_internal
