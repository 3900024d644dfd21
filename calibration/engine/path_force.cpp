// law_force_along (path_force.hpp): the engine's contact step (engine/lane_batch.hpp,
// LaneBatch::contacts) with one lane and the block placed on the path instead of integrated.
#include "engine/path_force.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/error.hpp"
#include "common/option_problems.hpp"
#include "engine/lane_step.hpp"

namespace ricochet {

namespace {

void check_path(std::span<const PathState> path) {
  for (std::size_t k = 0; k < path.size(); ++k) {
    const PathState& p = path[k];
    for (double v : {p.t_s, p.x_m, p.y_m, p.theta_rad, p.vx_mps, p.vy_mps, p.w_radps})
      if (!std::isfinite(v))
        throw InputError("<path>", k + 1, "state", "a state of the path is not finite");
    if (k > 0 && !(p.t_s > path[k - 1].t_s))
      throw InputError(
          "<path>", k + 1, "t_s",
          fmt::format("time {:g} s does not increase (previous {:g} s)", p.t_s, path[k - 1].t_s));
  }
}

}  // namespace

std::vector<PathForce> law_force_along(const Model& model, const Shape& shape,
                                       std::span<const PathState> path,
                                       std::span<const double> params,
                                       const EngineOptions& options) {
  require_valid(options.problems(), "law_force_along");
  check_path(path);
  std::vector<double> values =
      params.empty() ? model.values() : std::vector<double>(params.begin(), params.end());
  if (values.size() != model.parameter_count())
    throw std::invalid_argument(
        fmt::format("law_force_along: {} parameter values for a model of {}", values.size(),
                    model.parameter_count()));
  model.check(values);

  // One lane: each parameter is a pointer to its value, each state variable one double per
  // (effect, slot), zero at the start and whenever the slot leaves the contact (as the engine).
  const auto& effects = model.effects();
  const std::size_t slots = shape.vertices.size();
  std::vector<std::vector<const double*>> eparams(effects.size());
  std::vector<std::vector<double>> state(effects.size() * slots);
  std::vector<std::vector<double*>> state_ptr(effects.size() * slots);
  for (std::size_t e = 0; e < effects.size(); ++e) {
    for (std::size_t k = 0; k < effects[e]->parameters().size(); ++k)
      eparams[e].push_back(&values[model.offset(e) + k]);
    for (std::size_t s = 0; s < slots; ++s) {
      auto& st = state[e * slots + s];
      st.assign(effects[e]->state().size(), 0.0);
      for (double& v : st) state_ptr[e * slots + s].push_back(&v);
    }
  }
  std::vector<double> h_prev(slots, 0.0);
  // The surface under each slot, moved by effects that heap sand (Effect::moves_surface).
  bool lifts = false;
  for (const Effect* e : effects) lifts = lifts || e->moves_surface();
  std::vector<double> lift(slots, 0.0);

  const double r = shape.rounding_radius_m;
  // One contact step at state p over a step dt: every slot's effects, their history carried.
  const auto step = [&](const PathState& p, double dt) {
    const double c = std::cos(p.theta_rad), sn = std::sin(p.theta_rad);
    PathForce f;
    double deepest = 0;
    for (std::size_t s = 0; s < slots; ++s) {
      const double vbx = shape.vertices[s][0], vby = shape.vertices[s][1];
      const double px = p.x_m + c * vbx - sn * vby, py = p.y_m + sn * vbx + c * vby;
      double ground = 0.0, nx = 0.0, ny = 1.0;
      if (!options.ground.flat()) options.ground.surface(px, ground, nx, ny);
      ground += lift[s];
      const auto kc = detail::vertex_contact<false>(px, py, p.x_m, p.y_m, p.vx_mps, p.vy_mps,
                                                    p.w_radps, nx, ny, ground, r);
      double active = kc.active, h = kc.h, dh = kc.h - h_prev[s];
      double vn = kc.vn, vt = kc.vt, lever = kc.lever, w = p.w_radps, vx = p.vx_mps, vy = p.vy_mps;
      h_prev[s] = kc.h;
      // Out of contact an effect adds no force, raises no surface and leaves its state at zero
      // (invariant 2 of engine/effect_checks.hpp, checked over the registry; the engine's flight
      // jump rests on it too): the slot's effects need not run. Most of a track's sub-steps are
      // flight, or slots of a polygon off the ground.
      if (!(active > 0.0)) {
        for (std::size_t e = 0; e < effects.size(); ++e)
          for (double& v : state[e * slots + s]) v = 0.0;
        lift[s] = 0.0;
        continue;
      }
      double kf = 1, ef = 1, enf = 1, muf = 1, murf = 1;
      double fn = 0, ft = 0, mom = 0, fxb = 0, fyb = 0;
      ContactBatch cb;
      cb.n = 1;
      cb.dt = dt;
      cb.active = &active;
      cb.h = &h;
      cb.dh = &dh;
      cb.vn = &vn;
      cb.vt = &vt;
      cb.w = &w;
      cb.lever = &lever;
      cb.vx = &vx;
      cb.vy = &vy;
      cb.mass = shape.mass_kg;
      cb.length = shape.length_m;
      cb.kn_factor = &kf;
      cb.elastic_factor = &ef;
      cb.en2_factor = &enf;
      cb.mu_factor = &muf;
      cb.muR_factor = &murf;
      cb.fn = &fn;
      cb.ft = &ft;
      cb.moment = &mom;
      cb.fx_body = &fxb;
      cb.fy_body = &fyb;
      double lift_next = lift[s];
      if (lifts) {
        cb.lift = &lift[s];
        cb.lift_next = &lift_next;
      }
      for (std::size_t e = 0; e < effects.size(); ++e)
        effects[e]->apply(cb, eparams[e].data(), state_ptr[e * slots + s].data());
      lift[s] = active > 0.0 ? lift_next : 0.0;
      if (!(active > 0.0))
        for (std::size_t e = 0; e < effects.size(); ++e)
          for (double& v : state[e * slots + s]) v = 0.0;
      // The contact force acts at the contact point (engine/lane_batch.hpp, add_contact), the body
      // force at the centre of mass.
      const double fcx = fn * nx + ft * ny, fcy = fn * ny - ft * nx;
      f.fx_N += fcx + fxb;
      f.fy_N += fcy + fyb;
      f.torque_Nm += kc.rcx * fcy - kc.rcy * fcx + mom;
      if (kc.h > deepest) {
        deepest = kc.h;
        f.h_m = kc.h;
        f.vn_mps = kc.vn;
        f.vt_mps = kc.vt;
        f.lever_m = kc.lever;
        f.rcx_m = kc.rcx;
        f.rcy_m = kc.rcy;
        f.nx = nx;
        f.ny = ny;
        f.loading = dh > 0.0;
        f.fn_N = fn;
        f.ft_N = ft;
        f.moment_Nm = mom;
      }
    }
    return f;
  };

  // Between two states the path is the cubic Hermite curve through their positions and
  // velocities, walked in sub-steps of at most options.dt_s. Why: a track's records (0.2 ms)
  // are 20 engine steps apart; at that spacing the deepest point falls between records and the
  // incremental laws would take the record after it for loading (a (1 - e_n^2) kn h error at
  // that record), and the tangential spring would integrate a slip that changes within the
  // interval by a rectangle rule (errors of several kN on the independent simulator's traces).
  std::vector<PathForce> out(path.size());
  out[0] = step(path[0],
                path.size() > 1 ? std::min(options.dt_s, path[1].t_s - path[0].t_s) : options.dt_s);
  for (std::size_t k = 1; k < path.size(); ++k) {
    const PathState& a = path[k - 1];
    const PathState& b = path[k];
    const double T = b.t_s - a.t_s;
    const long n = std::max(1L, static_cast<long>(std::ceil(T / options.dt_s - 1e-9)));
    const auto hermite = [&](double p0, double v0, double p1, double v1, double u, double& p,
                             double& v) {
      const double u2 = u * u, u3 = u2 * u;
      p = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * T * v0 + (-2 * u3 + 3 * u2) * p1 +
          (u3 - u2) * T * v1;
      v = ((6 * u2 - 6 * u) * p0 + (3 * u2 - 4 * u + 1) * T * v0 + (-6 * u2 + 6 * u) * p1 +
           (3 * u2 - 2 * u) * T * v1) /
          T;
    };
    for (long j = 1; j <= n; ++j) {
      PathState q = b;
      if (j < n) {
        const double u = static_cast<double>(j) / static_cast<double>(n);
        q.t_s = a.t_s + u * T;
        hermite(a.x_m, a.vx_mps, b.x_m, b.vx_mps, u, q.x_m, q.vx_mps);
        hermite(a.y_m, a.vy_mps, b.y_m, b.vy_mps, u, q.y_m, q.vy_mps);
        hermite(a.theta_rad, a.w_radps, b.theta_rad, b.w_radps, u, q.theta_rad, q.w_radps);
      }
      const PathForce f = step(q, T / static_cast<double>(n));
      if (j == n) out[k] = f;
    }
  }
  return out;
}

}  // namespace ricochet
