#include "engine/effect_checks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "effects/model.hpp"
#include "effects/registry.hpp"
#include "engine/engine.hpp"

namespace ricochet {
namespace {

constexpr std::size_t kLanes = 8;
constexpr double kEnergyTolerance = 5e-4;  // relative to the incident kinetic energy

// A self-contained ContactBatch with its own storage, filled with a grid of contact states.
struct Fixture {
  std::array<double, kLanes> active{}, h{}, dh{}, vn{}, vt{}, w{}, lever{}, vx{}, vy{};
  std::array<double, kLanes> kf{}, ef{}, enf{}, muf{}, murf{};
  std::array<double, kLanes> fn{}, ft{}, moment{}, fxb{}, fyb{};
  std::array<double, kLanes> lift{}, lift_next{};  // a surface raised by half the overlap
  ContactBatch batch;

  Fixture(bool in_contact, double scale) {
    for (std::size_t i = 0; i < kLanes; ++i) {
      const double s = static_cast<double>(i) / (kLanes - 1);  // 0..1
      active[i] = in_contact ? 1.0 : 0.0;
      h[i] = in_contact ? scale * (1e-5 + 5e-3 * s) : 0.0;
      dh[i] = (i % 2 ? 1.0 : -1.0) * 1e-5 * scale;
      vn[i] = (i % 3 == 0 ? 1.0 : -1.0) * 4.0 * s * scale;
      vt[i] = (i % 2 ? -1.0 : 1.0) * 3.0 * s * scale;
      w[i] = -80.0 * s * scale;
      lever[i] = 0.08;
      vx[i] = 3.0 * s * scale;
      vy[i] = -2.5 * s * scale;
      kf[i] = ef[i] = enf[i] = muf[i] = murf[i] = 1.0;
      fn[i] = in_contact ? 1e4 * s : 0.0;  // what a normal stage would have produced
      lift[i] = lift_next[i] = 0.5 * h[i];
    }
    batch.n = kLanes;
    batch.dt = 1e-5;
    batch.active = active.data();
    batch.h = h.data();
    batch.dh = dh.data();
    batch.vn = vn.data();
    batch.vt = vt.data();
    batch.w = w.data();
    batch.lever = lever.data();
    batch.vx = vx.data();
    batch.vy = vy.data();
    batch.mass = 13.9;
    batch.length = 0.29;
    batch.kn_factor = kf.data();
    batch.elastic_factor = ef.data();
    batch.en2_factor = enf.data();
    batch.mu_factor = muf.data();
    batch.muR_factor = murf.data();
    batch.fn = fn.data();
    batch.ft = ft.data();
    batch.moment = moment.data();
    batch.fx_body = fxb.data();
    batch.fy_body = fyb.data();
    batch.lift = lift.data();
    batch.lift_next = lift_next.data();
  }
};

// Runs apply() with every parameter at `value_of(spec)`, `steps` times, on `fx`.
template <class ValueOf>
std::vector<std::vector<double>> run(const Effect& effect, Fixture& fx, ValueOf value_of,
                                     int steps) {
  const auto specs = effect.parameters();
  std::vector<std::vector<double>> params(specs.size(), std::vector<double>(kLanes));
  std::vector<const double*> pptr;
  for (std::size_t k = 0; k < specs.size(); ++k) {
    for (auto& v : params[k]) v = value_of(specs[k]);
    pptr.push_back(params[k].data());
  }
  std::vector<std::vector<double>> state(effect.state().size(), std::vector<double>(kLanes, 0.0));
  std::vector<double*> sptr;
  for (auto& s : state) sptr.push_back(s.data());
  for (int k = 0; k < steps; ++k) effect.apply(fx.batch, pptr.data(), sptr.data());
  return state;
}

bool all_finite(const std::array<double, kLanes>& a) {
  for (double v : a)
    if (!std::isfinite(v)) return false;
  return true;
}

bool unchanged(const std::array<double, kLanes>& a, const std::array<double, kLanes>& b) {
  return a == b;
}

std::string name_of(const Effect& e) {
  return "effect '" + std::string(e.name()) + "': ";
}

}  // namespace

namespace {

using Problems = std::vector<std::string>;
using BoundOf = double (*)(const ParameterSpec&);
double at_lower(const ParameterSpec& p) {
  return p.lower;
}
double at_nominal(const ParameterSpec& p) {
  return p.nominal;
}
double at_upper(const ParameterSpec& p) {
  return p.upper;
}

// 1. Declarations: names, units, bounds holding the nominal and neutral values, the equation and
// its reference.
void check_declarations(const Effect& effect, const std::string& who, Problems& problems) {
  for (const auto& p : effect.parameters()) {
    if (p.name.empty() || p.unit.empty())
      problems.push_back(who + "a parameter lacks a name or a unit");
    if (!(p.lower <= p.nominal && p.nominal <= p.upper))
      problems.push_back(who + "nominal value of '" + std::string(p.name) + "' outside bounds");
    if (!std::isnan(p.neutral) && !(p.lower <= p.neutral && p.neutral <= p.upper))
      problems.push_back(who + "neutral value of '" + std::string(p.name) + "' outside bounds");
  }
  if (effect.equation().empty() || effect.reference().empty())
    problems.push_back(who + "equation and reference must be documented");
}

// 2. Out of contact: no force, state zero.
void check_out_of_contact(const Effect& effect, const std::string& who, Problems& problems) {
  Fixture fx(false, 1.0);
  const Fixture before = fx;
  const auto state = run(effect, fx, at_nominal, 3);
  if (!unchanged(fx.fn, before.fn) || !unchanged(fx.ft, before.ft) ||
      !unchanged(fx.moment, before.moment) || !unchanged(fx.fxb, before.fxb) ||
      !unchanged(fx.fyb, before.fyb))
    problems.push_back(who + "adds a force or moment out of contact");
  if (!unchanged(fx.lift_next, before.lift_next))
    problems.push_back(who + "raises the surface out of contact");
  for (const auto& s : state)
    for (double v : s)
      if (v != 0.0) problems.push_back(who + "keeps a non-zero state out of contact");
}

// 3 and 4. Stage discipline (an effect writes only its stage's output) and finite outputs, with
// the parameters at each bound and the penetration from zero to ten times the fixture's.
void check_stage_and_finiteness(const Effect& effect, const std::string& who, Problems& problems) {
  for (BoundOf value_of : {at_lower, at_nominal, at_upper}) {
    for (double scale : {0.0, 0.1, 1.0, 10.0}) {
      Fixture fx(true, scale);
      const Fixture before = fx;
      const auto state = run(effect, fx, value_of, 5);
      const Stage st = effect.stage();
      const bool factors_same = unchanged(fx.kf, before.kf) && unchanged(fx.ef, before.ef) &&
                                unchanged(fx.enf, before.enf) && unchanged(fx.muf, before.muf) &&
                                unchanged(fx.murf, before.murf);
      if (st != Stage::kCoefficient && !factors_same)
        problems.push_back(who + "changes coefficient factors but is not a coefficient effect");
      if (st != Stage::kNormal && !unchanged(fx.fn, before.fn))
        problems.push_back(who + "writes fn but its stage is " + std::string(stage_name(st)));
      if (st != Stage::kTangential && !unchanged(fx.ft, before.ft))
        problems.push_back(who + "writes ft but its stage is " + std::string(stage_name(st)));
      if (st != Stage::kRolling && !unchanged(fx.moment, before.moment))
        problems.push_back(who + "writes the moment but its stage is " +
                           std::string(stage_name(st)));
      if (st != Stage::kBody && (!unchanged(fx.fxb, before.fxb) || !unchanged(fx.fyb, before.fyb)))
        problems.push_back(who + "writes body forces but its stage is " +
                           std::string(stage_name(st)));
      if (!effect.moves_surface() && !unchanged(fx.lift_next, before.lift_next))
        problems.push_back(who +
                           "moves the surface (lift_next) but does not declare moves_surface()");
      bool finite = all_finite(fx.fn) && all_finite(fx.ft) && all_finite(fx.moment) &&
                    all_finite(fx.fxb) && all_finite(fx.fyb) && all_finite(fx.kf) &&
                    all_finite(fx.ef) && all_finite(fx.enf) && all_finite(fx.muf) &&
                    all_finite(fx.murf) && all_finite(fx.lift_next);
      for (const auto& s : state)
        for (double v : s) finite = finite && std::isfinite(v);
      if (!finite) {
        std::ostringstream msg;
        msg << who << "non-finite output at penetration scale " << scale
            << " with parameters at a bound";
        problems.push_back(msg.str());
      }
    }
  }
}

const std::array<CollisionCase, 3> kCases = {CollisionCase{{2.9, -2.3, -65.0}, 0.0},
                                             CollisionCase{{0.0, -4.0, 0.0}, 0.0},
                                             CollisionCase{{4.5, -3.5, -30.0}, 0.4}};

// 5. In the real engine, added to the paper's law: no energy created, parameters at each bound,
// both shapes.
void check_energy(const Effect& effect, const Model& model, const EngineOptions& options,
                  const std::string& who, Problems& problems) {
  for (const Shape& shape : {Shape::cylinder(), Shape::triangle()}) {
    for (BoundOf value_of : {at_lower, at_nominal, at_upper}) {
      std::vector<double> values = model.values();
      for (const auto& p : effect.parameters()) values[model.index(p.name)] = value_of(p);
      // Resolve the stiffest spring at the bounds (stiffnesses up to 1e10 N m/rad).
      EngineOptions at_bounds = options;
      at_bounds.dt_s = std::min(options.dt_s, 0.02 * critical_time_step(model, shape, values));
      for (const auto& c : kCases) {
        const CollisionResult r = simulate(model, shape, c, values, at_bounds);
        const double gained = r.kinetic_out_J + r.potential_change_J - r.kinetic_in_J;
        // Tolerance: the integrator's own error on a perfectly elastic contact (e_n^2 = 1).
        if (gained > kEnergyTolerance * r.kinetic_in_J) {
          std::ostringstream msg;
          msg << who << "creates " << gained << " J in a " << shape.name << " collision";
          problems.push_back(msg.str());
        }
      }
    }
  }
}

// 6. At its neutral values (when every parameter has one) the effect leaves the paper's law as
// it is.
void check_neutral(const Effect& effect, const Model& base, const Model& model,
                   const EngineOptions& options, const std::string& who, Problems& problems) {
  const auto specs = effect.parameters();
  bool has_neutral = !specs.empty();
  for (const auto& p : specs) has_neutral = has_neutral && !std::isnan(p.neutral);
  if (!has_neutral || base.has_effect(effect.name())) return;
  std::vector<double> values = model.values();
  for (const auto& p : specs) values[model.index(p.name)] = p.neutral;
  for (const auto& c : kCases) {
    const CollisionResult a = simulate(base, Shape::cylinder(), c, {}, options);
    const CollisionResult b = simulate(model, Shape::cylinder(), c, values, options);
    if (a.vout != b.vout)
      problems.push_back(who + "at its neutral values it changes the paper's law");
  }
}

}  // namespace

std::vector<std::string> check_effect_invariants(const Effect& effect) {
  Problems problems;
  const std::string who = name_of(effect);
  check_declarations(effect, who, problems);
  check_out_of_contact(effect, who, problems);
  check_stage_and_finiteness(effect, who, problems);
  if (!problems.empty()) return problems;

  EffectRegistry registry = EffectRegistry::with_builtins();
  if (!registry.contains(effect.name())) registry.add_borrowed(effect);
  const Model base = Model::paper(registry);
  Model model = base;
  if (!base.has_effect(effect.name())) model = base.with_effect(effect.name(), false, registry);
  EngineOptions options;
  options.max_time_s = 0.3;
  check_energy(effect, model, options, who, problems);
  check_neutral(effect, base, model, options, who, problems);
  return problems;
}

}  // namespace ricochet
