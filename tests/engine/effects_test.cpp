// The effect registry, model composition, and the invariants of every registered effect.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "effects/catalog.hpp"
#include "effects/model.hpp"
#include "effects/registry.hpp"
#include "engine/effect_checks.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"

namespace ricochet {
namespace {

// One generic check over the whole registry (LAMMPS force-style tests do the same per style).
TEST(Effects, EveryRegisteredEffectSatisfiesTheInvariants) {
  const auto registry = EffectRegistry::with_builtins();
  ASSERT_GE(registry.names().size(), 8u);
  for (const Effect* e : registry.all()) {
    const auto problems = check_effect_invariants(*e);
    EXPECT_TRUE(problems.empty()) << e->name() << ": " << (problems.empty() ? "" : problems[0]);
  }
}

// One contact lane for an effect driven by hand: every input and output of ContactBatch as a
// named double, the batch pointing at them.
struct OneLane {
  double active = 1, h = 0, dh = 0, vn = 0, vt = 0, w = 0, lever = 0.08, vx = 0, vy = 0;
  double kf = 1, ef = 1, enf = 1, muf = 1, murf = 1, fn = 0, ft = 0, mom = 0, fx = 0, fy = 0;
  double lift = 0, lift_next = 0;
  ContactBatch batch(double dt) {
    ContactBatch c;
    c.n = 1, c.dt = dt, c.active = &active, c.h = &h, c.dh = &dh, c.vn = &vn, c.vt = &vt;
    c.w = &w, c.lever = &lever, c.vx = &vx, c.vy = &vy, c.mass = 13.9, c.length = 0.29;
    c.kn_factor = &kf, c.elastic_factor = &ef, c.en2_factor = &enf, c.mu_factor = &muf;
    c.muR_factor = &murf, c.fn = &fn, c.ft = &ft, c.moment = &mom, c.fx_body = &fx;
    c.fy_body = &fy, c.lift = &lift, c.lift_next = &lift_next;
    return c;
  }
};

// crater_ramp by hand: a contact that reached h_max = 3 mm, then moves along x at constant depth
// 2 mm (1 mm risen) at 2 m/s. After n steps of dt its travel is s = 2 n dt, its overlap with a
// ramp of slope 0.25 is delta = 0.25 s - 1 mm once positive, and the wall pushes with k delta
// up and tan_beta k delta back; a deeper step resets the travel; out of contact nothing.
TEST(Effects, CraterRampIsTheOverlapWithARampRisingAheadOfTheBlock) {
  const auto registry = EffectRegistry::with_builtins();
  const Effect& e = registry.get("crater_ramp");
  ASSERT_FALSE(e.default_candidate());
  const double dt = 1e-3, tb = 0.25, k = 2e6;
  OneLane l;
  l.h = 0.003, l.vx = 2.0;
  double &active = l.active, &h = l.h, &vx = l.vx, &fx = l.fx, &fy = l.fy;
  double h_max = 0, s = 0;
  const ContactBatch c = l.batch(dt);
  const double params[] = {tb, k};
  const double* p[] = {&params[0], &params[1]};
  double* st[] = {&h_max, &s};
  e.apply(c, p, st);  // the deepest point: travel starts from 0
  EXPECT_EQ(h_max, 0.003);
  EXPECT_EQ(s, 0.0);
  EXPECT_EQ(fy, 0.0);
  h = 0.002;
  for (int n = 1; n <= 5; ++n) {
    fx = fy = 0;
    e.apply(c, p, st);
    const double travel = 2.0 * n * dt, delta = std::max(0.0, tb * travel - 0.001);
    EXPECT_NEAR(s, travel, 1e-15) << n;
    EXPECT_NEAR(fy, k * delta, 1e-9) << n;
    EXPECT_NEAR(fx, -tb * k * delta, 1e-9) << n;
  }
  EXPECT_GT(fy, 0.0);  // 0.25 x 10 mm - 1 mm = 1.5 mm of overlap
  vx = -2.0;           // moving back: the ramp behind, pushing forward
  for (int n = 0; n < 10; ++n) e.apply(c, p, st);
  fx = fy = 0;
  e.apply(c, p, st);
  EXPECT_NEAR(s, -0.012, 1e-12);
  EXPECT_NEAR(fx, tb * k * (tb * 0.012 - 0.001), 1e-9);
  h = 0.004;  // deeper than ever: a new deepest point, no travel, no wall
  fx = fy = 0;
  e.apply(c, p, st);
  EXPECT_EQ(h_max, 0.004);
  EXPECT_EQ(s, 0.0);
  EXPECT_EQ(fy, 0.0);
  active = 0, h = 0;  // out of contact: no force, the state cleared
  e.apply(c, p, st);
  EXPECT_EQ(fy, 0.0);
  EXPECT_EQ(h_max, 0.0);
  EXPECT_EQ(s, 0.0);
}

// crater_rim by hand: a contact 2 mm below the undisturbed ground moving along x at 2 m/s, the
// surface under it carried from step to step as the engine carries it (lift <- lift_next).
// After n steps of dt the swept area is A = 2 mm x 2 n dt (the depth below the undisturbed
// ground is h - L, and h is held at L + 2 mm), the heap sqrt(2 tan_phi A), and the surface
// follows it no faster than tan_phi per metre of travel: first at that slope, then on the heap's
// square root. The reaction is the slope climbed times fn, against the travel. Pressed with more
// than w_rim = 1 block weight, the heap yields: it does not rise and does not push back.
TEST(Effects, CraterRimHeapsTheSweptSandAndTheBlockClimbsIt) {
  const auto registry = EffectRegistry::with_builtins();
  const Effect& e = registry.get("crater_rim");
  ASSERT_FALSE(e.default_candidate());
  ASSERT_TRUE(e.moves_surface());
  // fn0 below the block's weight (13.9 kg x 9.81 = 136 N): the heap carries it (w_rim = 1).
  const double dt = 1e-4, tp = 0.5, d = 0.002, v = 2.0, fn0 = 100.0;
  OneLane l;
  l.h = d, l.vx = v, l.fn = fn0;
  double &active = l.active, &h = l.h, &vx = l.vx, &fx = l.fx, &fy = l.fy;
  double &lift = l.lift, &lift_next = l.lift_next;
  double area = 0;
  const ContactBatch c = l.batch(dt);
  const double params[] = {tp, 1.0};
  const double* p[] = {&params[0], &params[1]};
  double* st[] = {&area};
  double expected_lift = 0;
  bool saw_slope = false, saw_heap = false;
  for (int n = 1; n <= 400; ++n) {
    fx = fy = 0;
    lift_next = lift;
    h = lift + d;
    e.apply(c, p, st);
    const double a = d * v * n * dt;
    EXPECT_NEAR(area, a, 1e-15) << n;
    const double next = std::min(std::sqrt(2 * tp * a), expected_lift + tp * v * dt);
    saw_slope = saw_slope || next < std::sqrt(2 * tp * a);
    saw_heap = saw_heap || next < expected_lift + tp * v * dt;
    EXPECT_NEAR(lift_next, next, 1e-12) << n;
    EXPECT_NEAR(fx, -fn0 * (next - expected_lift) / (v * dt), 1e-9) << n;
    EXPECT_LE(-fx, tp * fn0 * (1 + 1e-12)) << n;  // never steeper than the heap's face
    EXPECT_EQ(fy, 0.0);
    expected_lift = next;
    lift = lift_next;
  }
  EXPECT_TRUE(saw_slope && saw_heap);  // both branches of the min were exercised
  // 80 mm of travel at 2 mm depth: A = 1.6e-4 m^2, a heap of sqrt(2 x 0.5 x A) = 12.6 mm.
  EXPECT_NEAR(lift, std::sqrt(2 * tp * d * v * 400 * dt), 1e-12);
  // Pressed with more than the block's weight, the heap yields: the swept sand still counts, the
  // surface does not rise, and nothing pushes back.
  l.fn = 200.0;
  fx = 0;
  lift_next = lift;
  h = lift + d;
  const double before = area;
  e.apply(c, p, st);
  EXPECT_NEAR(area, before + d * v * dt, 1e-15);
  EXPECT_EQ(lift_next, lift);
  EXPECT_EQ(fx, 0.0);
  l.fn = fn0;
  vx = -v;  // moving back: the reaction turns, still against the travel
  fx = 0;
  lift_next = lift;
  h = lift + d;
  e.apply(c, p, st);
  EXPECT_GT(fx, 0.0);
  active = 0, h = 0;  // out of contact: no force, state and surface cleared
  fx = 0;
  e.apply(c, p, st);
  EXPECT_EQ(fx, 0.0);
  EXPECT_EQ(area, 0.0);
  EXPECT_EQ(lift_next, 0.0);
}

// In the engine, on a soft plastic contact like the one the stiff resolved bed's ladder fits
// (kn 4e6 N/m, e_n^2 0.05, mu 1.6, mu_R 0.2; docs/diagnosis.md, "Added: the rim"), the heap
// carries the block out of its crater: the contact lasts the longer the steeper the heap's face,
// the block leaves faster upwards and slower along the ground than on flat ground, and the
// penetration kept, the depth below the undisturbed ground, is no deeper; at tan_phi = 0, the
// law itself, bit for bit.
TEST(Effects, CraterRimCarriesTheBlockOut) {
  const auto registry = EffectRegistry::with_builtins();
  const Model base = Model::paper(registry);
  const Model rim = base.with_effect("crater_rim", false, registry);
  const CollisionCase c{{2.9, -2.3, -65.0}, 0.0};
  std::vector<double> b = base.values(), r = rim.values();
  for (const auto& [name, value] : std::vector<std::pair<std::string, double>>{
           {"kn", 4e6}, {"en2", 0.05}, {"mu", 1.6}, {"muR", 0.2}}) {
    b[base.index(name)] = value;
    r[rim.index(name)] = value;
  }
  r[rim.index("tan_phi")] = 0.0;
  const CollisionResult flat = simulate(base, Shape::cylinder(), c, b);
  const CollisionResult neutral = simulate(rim, Shape::cylinder(), c, r);
  EXPECT_EQ(neutral.vout, flat.vout);
  EXPECT_EQ(neutral.max_penetration_m, flat.max_penetration_m);
  double longer = flat.contact_duration_s;
  for (double tp : {0.2, 0.4, 0.8}) {
    r[rim.index("tan_phi")] = tp;
    const CollisionResult heaped = simulate(rim, Shape::cylinder(), c, r);
    EXPECT_GT(heaped.contact_duration_s, longer) << tp;
    EXPECT_LE(heaped.max_penetration_m, flat.max_penetration_m) << tp;
    longer = heaped.contact_duration_s;
  }
  r[rim.index("tan_phi")] = 0.8;
  const CollisionResult steep = simulate(rim, Shape::cylinder(), c, r);
  EXPECT_GT(steep.contact_duration_s, 2 * flat.contact_duration_s);
  EXPECT_GT(steep.vout[kVy], flat.vout[kVy] + 0.03);
  EXPECT_LT(steep.vout[kVx], flat.vout[kVx] - 0.05);
}

// The checker itself must catch a broken effect, or the test above proves nothing.
class LeakyEffect final : public Effect {
 public:
  std::string_view name() const override { return "leaky"; }
  std::string_view summary() const override { return "pushes even out of contact"; }
  std::string_view equation() const override { return "fn += 1"; }
  std::string_view reference() const override { return "a test"; }
  Stage stage() const override { return Stage::kNormal; }
  LawKind kind() const override { return {Family::kOther, Variable::kOther}; }
  std::span<const ParameterSpec> parameters() const override { return {}; }
  void apply(const ContactBatch& c, const double* const*, double* const*) const override {
    for (std::size_t i = 0; i < c.n; ++i) c.fn[i] += 1.0;
  }
};

class EnergyPump final : public Effect {
 public:
  std::string_view name() const override { return "pump"; }
  std::string_view summary() const override { return "pushes along the velocity"; }
  std::string_view equation() const override { return "fx += k * vx"; }
  std::string_view reference() const override { return "a test"; }
  Stage stage() const override { return Stage::kBody; }
  LawKind kind() const override { return {Family::kOther, Variable::kOther}; }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  void apply(const ContactBatch& c, const double* const* p, double* const*) const override {
    for (std::size_t i = 0; i < c.n; ++i) c.fx_body[i] += c.active[i] * p[0][i] * c.vx[i];
  }
  static constexpr ParameterSpec kParams[] = {{"k", "N s/m", 0, 1e4, 1e3, 0, true, "gain"}};
};

TEST(Effects, CheckerCatchesBrokenEffects) {
  EXPECT_FALSE(check_effect_invariants(LeakyEffect{}).empty());
  const auto pump = check_effect_invariants(EnergyPump{});
  ASSERT_FALSE(pump.empty());
  EXPECT_NE(pump[0].find("creates"), std::string::npos) << pump[0];
}

TEST(Effects, UnknownNameListsKnownNames) {
  try {
    Model::from_names({"normal", "tangentail"});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unknown effect 'tangentail'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("tangential"), std::string::npos) << msg;
    EXPECT_NE(msg.find("rate_restitution"), std::string::npos) << msg;
  }
}

// What the registry checks when it stores an effect, whoever wrote it: one declaration that it
// cannot read is enough to refuse the effect, with a message naming what is wrong.
class Declared final : public Effect {
 public:
  std::string_view name() const override { return "declared"; }
  std::string_view summary() const override { return "a declaration under test"; }
  std::string_view equation() const override { return "fn += 0"; }
  std::string_view reference() const override { return "a test"; }
  Stage stage() const override { return Stage::kNormal; }
  LawKind kind() const override { return kind_; }
  std::span<const ParameterSpec> parameters() const override { return params_; }
  std::span<const StateSpec> state() const override { return state_; }
  Signature signature() const override { return {"a test", trends_}; }
  FusedLaw fused_law() const override { return fused_; }
  void apply(const ContactBatch&, const double* const*, double* const*) const override {}

  std::vector<ParameterSpec> params_ = {{"k", "N/m", 0, 1, 0.5, NAN, false, "a stiffness"},
                                        {"e", "-", 0, 1, 0.5, NAN, true, "a restitution"}};
  std::vector<StateSpec> state_ = {{"fn", "N"}};
  std::vector<SignatureTrend> trends_;
  FusedLaw fused_ = FusedLaw::kNone;
  LawKind kind_ = {Family::kOther, Variable::kOther};
};

// The message of the std::invalid_argument that `f` throws, or "accepted".
template <class F>
std::string refusal_of(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

std::string refusal(const Declared& effect) {
  EffectRegistry r;
  const std::string what = refusal_of([&] { r.add_borrowed(effect); });
  EXPECT_EQ(r.contains("declared"), what == "accepted");
  return what;
}

TEST(Registry, RefusesADeclarationItCannotRead) {
  EXPECT_EQ(refusal(Declared{}), "accepted");
  Declared fused;  // the fused kernel would read its kn and e_n^2 by role
  fused.fused_ = FusedLaw::kPaperNormal;
  EXPECT_NE(refusal(fused).find("needs exactly one parameter of role normal_stiffness, not 0"),
            std::string::npos)
      << refusal(fused);
  fused.params_[0].role = ParameterRole::kNormalStiffness;
  fused.params_[1].role = ParameterRole::kRestitution;
  EXPECT_EQ(refusal(fused), "accepted");
  fused.state_.clear();
  EXPECT_NE(refusal(fused).find("state variable"), std::string::npos) << refusal(fused);

  Declared word;
  word.trends_ = {{"residual vy", "abs_vin_y"}, {"residual v", "speed_in"}};
  EXPECT_NE(refusal(word).find("effect 'declared': signature: unknown signature quantity "
                               "'residual v'; known quantities: residual vx, residual vy"),
            std::string::npos)
      << refusal(word);
  word.trends_ = {{"param friction_cap", "penetration"}};
  EXPECT_EQ(refusal(word), "accepted");

  Declared cast;  // an enum value this build does not know (a plugin built against a newer one)
  cast.params_[1].role = static_cast<ParameterRole>(kParameterRoleCount);
  EXPECT_NE(refusal(cast).find("declares the role of 'e' 8, which is unknown"), std::string::npos)
      << refusal(cast);
  cast = Declared{};
  cast.kind_.family = static_cast<Family>(kFamilyCount);
  EXPECT_NE(refusal(cast).find("family"), std::string::npos) << refusal(cast);
}

// A parameter trend names a role, not a parameter: "param en2" is refused with the known words.
TEST(Registry, AParameterTrendNamesARoleNotAName) {
  EXPECT_EQ(parse_trend({"param restitution", "speed_in"}).parameter, ParameterRole::kRestitution);
  const std::string msg = refusal_of([] { (void)parse_trend({"param en2", "speed_in"}); });
  EXPECT_NE(msg.find("unknown signature quantity 'param en2'; known quantities: residual vx"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("param <role> with role in {normal_stiffness, tangential_stiffness"),
            std::string::npos)
      << msg;
  EXPECT_NE(refusal_of([] { (void)parse_trend({"param other", "speed_in"}); }), "accepted");
}

// docs/effects/README.md is `ricochet effects --markdown`: regenerate it after changing an
// effect's declaration (build/cli/ricochet effects --markdown > docs/effects/README.md).
TEST(EffectCatalog, CommittedPageIsTheGeneratedOne) {
  std::ifstream in(std::string(RICOCHET_SOURCE_DIR) + "/docs/effects/README.md");
  ASSERT_TRUE(in) << "docs/effects/README.md is missing";
  std::stringstream text;
  text << in.rdbuf();
  const std::string generated = effects::catalog_markdown(EffectRegistry::with_builtins());
  // Line by line, so that a failure shows the first stale line rather than two whole pages.
  std::istringstream committed(text.str()), fresh(generated);
  std::string a, b;
  for (int line = 1; std::getline(fresh, b); ++line) {
    const bool more = static_cast<bool>(std::getline(committed, a));
    if (!more || a != b) {
      ADD_FAILURE() << "docs/effects/README.md line " << line
                    << " differs from `ricochet effects --markdown` (regenerate it):\n  committed: "
                    << (more ? a : "<end of file>") << "\n  generated: " << b;
      break;
    }
  }
  EXPECT_TRUE(text.str() == generated) << "regenerate docs/effects/README.md";
  // The page is the declarations, not a copy of them: every built-in's row and its roles.
  EXPECT_NE(generated.find("| hertz_stiffness | coefficient | stiffness | penetration |"),
            std::string::npos);
  EXPECT_NE(generated.find("`kn` [N/m] 100000 to 1e+09, normal_stiffness, fixed (identified by "
                           "contact_features)"),
            std::string::npos);
}

TEST(Effects, ModelCompositionRules) {
  EXPECT_THROW(Model::from_names({"tangential", "rolling"}), std::invalid_argument);  // no normal
  EXPECT_THROW(Model::from_names({"normal", "normal"}), std::invalid_argument);
  const Model m = Model::from_names({"rolling", "rate_restitution", "normal", "tangential"});
  // Stage order: coefficient, normal, tangential, rolling.
  EXPECT_EQ(m.effect_names(),
            (std::vector<std::string>{"rate_restitution", "normal", "tangential", "rolling"}));
  EXPECT_EQ(m.parameter_names(),
            (std::vector<std::string>{"kv", "kn", "en2", "kt", "mu", "kr", "muR"}));
  EXPECT_THROW(m.index("nope"), std::invalid_argument);
}

TEST(Effects, OutOfBoundValuesAreRejectedWithTheAllowedRange) {
  Model m = Model::paper();
  try {
    m.set("en2", 1.5);
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("[0, 1]"), std::string::npos) << e.what();
  }
  // Every parameter of every effect: both sides of both bounds.
  const auto registry = EffectRegistry::with_builtins();
  for (const Effect* e : registry.all()) {
    Model model = Model::paper(registry);
    if (!model.has_effect(e->name())) model = model.with_effect(e->name(), false, registry);
    for (const auto& p : e->parameters()) {
      EXPECT_NO_THROW(model.set(p.name, p.lower));
      EXPECT_NO_THROW(model.set(p.name, p.upper));
      EXPECT_THROW(model.set(p.name, p.upper + 1e-9 * (1 + std::fabs(p.upper))), std::out_of_range)
          << p.name;
      EXPECT_THROW(model.set(p.name, p.lower - 1e-9 * (1 + std::fabs(p.lower))), std::out_of_range)
          << p.name;
    }
  }
}

TEST(Effects, WithEffectAtNeutralStartsWhereTheBaseModelIs) {
  Model base = Model::paper();
  base.set("en2", 0.2);
  const Model m = base.with_effect("inertial_drag", true);
  EXPECT_EQ(m.value("en2"), 0.2);
  EXPECT_EQ(m.value("cd"), 0.0);
}

TEST(Effects, ModelFileErrorsNameFileLineAndKey) {
  const std::string text =
      "effects = [\"normal\", \"tangential\", \"rolling\"]\n"
      "[parameters]\n"
      "en2 = 0.2\n"
      "mu = 7.0\n";
  try {
    Model::from_toml_string(text, "model.toml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "model.toml");
    EXPECT_EQ(e.line(), 4u);
    EXPECT_EQ(e.field(), "parameters.mu");
  }
  try {
    Model::from_toml_string("effects = [\"normal\", \"drag\"]\n", "m.toml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1u);
    EXPECT_NE(std::string(e.what()).find("inertial_drag"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Model::from_toml_string("effect = [\"normal\"]\n", "m.toml"), InputError);
}

TEST(Effects, ModelFileRoundTrip) {
  Model m = Model::paper().with_effect("depth_friction");
  m.set("a_mu", 120.0);
  m.set_bounds("mu", 0.0, 1.0);
  m.set_calibrated("kn", true);
  const Model back = Model::from_toml_string(m.to_toml(), "roundtrip.toml");
  EXPECT_EQ(back.effect_names(), m.effect_names());
  EXPECT_EQ(back.values(), m.values());
  EXPECT_EQ(back.upper(back.index("mu")), 1.0);
  EXPECT_EQ(back.calibrated_indices(), m.calibrated_indices());
  // A model without held parameters writes no `hold` key (files written before it read back to
  // the same text); one with them writes it and reads it back.
  EXPECT_EQ(m.to_toml().find("hold"), std::string::npos);
  Model held = m;
  held.set_held("kn", true);
  EXPECT_FALSE(held.calibrated(held.index("kn")));
  const Model held_back = Model::from_toml_string(held.to_toml(), "held.toml");
  EXPECT_TRUE(held_back.held(held_back.index("kn")));
  EXPECT_FALSE(held_back.held(held_back.index("en2")));
  EXPECT_EQ(held_back.to_toml(), held.to_toml());
}

// A held parameter is never calibrated: asking for both is an error naming the file, line and
// key, and so is an unknown name (listing the model's names).
TEST(Effects, HeldParametersCannotBeCalibrated) {
  const std::string effects = "effects = [\"normal\", \"tangential\", \"rolling\"]\n";
  for (const auto& [text, needle] : std::vector<std::pair<std::string, std::string>>{
           {effects + "calibrate = [\"en2\"]\nhold = [\"en2\"]\n", "both"},
           {effects + "hold = [\"k_n\"]\n", "kn"},
           {effects + "hold = [1]\n", "strings"}}) {
    try {
      Model::from_toml_string(text, "m.toml");
      ADD_FAILURE() << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "m.toml");
      EXPECT_EQ(e.field(), "hold") << text;
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  }
  // Holding a parameter the default would calibrate takes it out of the calibrated set.
  const Model m = Model::from_toml_string(effects + "hold = [\"mu\"]\n", "m.toml");
  std::vector<std::string> names;
  for (auto i : m.calibrated_indices()) names.emplace_back(m.spec(i).name);
  EXPECT_EQ(names, (std::vector<std::string>{"en2", "muR"}));
  Model copy = m;
  EXPECT_THROW(copy.set_calibrated("mu", true), std::invalid_argument);
  // with_effect keeps what is held.
  EXPECT_TRUE(m.with_effect("crater_rim").held(m.index("mu")));
}

// Found by fuzz/fuzz_model_toml: `calibrate = 0` was silently ignored (so were `parameters` and
// `bounds` that are not tables), and a bound of -0.0 was written as "-0", which reads back as
// +0.0: the round trip was not exact.
TEST(Effects, MistypedModelKeysAreErrorsAndNegativeZeroRoundTrips) {
  const std::string effects = "effects = [\"normal\", \"tangential\", \"rolling\"]\n";
  for (const auto& [text, field] : std::vector<std::pair<std::string, std::string>>{
           {effects + "calibrate = 0\n", "calibrate"},
           {effects + "parameters = [1]\n", "parameters"},
           {effects + "bounds = \"none\"\n", "bounds"},
           {"effects = \"normal\"\n", "effects"}}) {
    try {
      Model::from_toml_string(text, "m.toml");
      ADD_FAILURE() << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "m.toml");
      EXPECT_EQ(e.field(), field) << text;
      EXPECT_EQ(e.line(), field == "effects" ? 1u : 2u) << text;
    }
  }
  const Model m = Model::from_toml_string(effects + "[bounds]\nmu = [-0.0, 0.1]\n", "m.toml");
  const std::string text = m.to_toml();
  const Model back = Model::from_toml_string(text, "back.toml");
  EXPECT_TRUE(std::signbit(back.lower(back.index("mu")))) << text;
  EXPECT_EQ(back.to_toml(), text);
}

TEST(Shapes, FilesMatchBuiltIns) {
  const std::filesystem::path dir = std::filesystem::path(RICOCHET_SOURCE_DIR) / "data/shapes";
  for (const Shape& builtin : {Shape::cylinder(), Shape::triangle()}) {
    const Shape file = Shape::from_toml_file((dir / (builtin.name + ".toml")).string());
    EXPECT_EQ(file.vertices, builtin.vertices);
    EXPECT_EQ(file.rounding_radius_m, builtin.rounding_radius_m);
    EXPECT_EQ(file.mass_kg, builtin.mass_kg);
    EXPECT_EQ(file.inertia_kgm2, builtin.inertia_kgm2);
    EXPECT_EQ(file.length_m, builtin.length_m);  // the drop check carries drag to the block
  }
  // The triangle's geometry reproduces the lab block's radius of gyration within 1 %.
  const Shape t = Shape::triangle();
  const double a = std::hypot(t.vertices[1][0] - t.vertices[2][0], 0.0);  // side
  const double r = t.rounding_radius_m;
  const double at = std::sqrt(3.0) / 4 * a * a, rin = a / (2 * std::sqrt(3.0)),
               rc = a / std::sqrt(3.0);
  const double area = at + 3 * a * r + M_PI * r * r;
  const double j = at * a * a / 12 + 3 * a * r * ((a * a + r * r) / 12 + std::pow(rin + r / 2, 2)) +
                   M_PI * std::pow(r, 4) / 2 +
                   M_PI * r * r * (rc * rc + 2 * rc * r * std::sqrt(3.0) / M_PI);
  EXPECT_NEAR(std::sqrt(j / area), std::sqrt(t.inertia_kgm2 / t.mass_kg), 0.01 * 0.0593);
}

TEST(Shapes, FileErrorsNameTheKey) {
  const auto path = std::filesystem::temp_directory_path() / "ricochet_bad_shape.toml";
  std::ofstream(path) << "name = \"x\"\nvertices = [[0.0, 0.0]]\nrounding_radius_m = 0.1\n"
                         "mass_kg = -1\ninertia_kgm2 = 0.1\n";
  try {
    Shape::from_toml_file(path.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "mass_kg");
  }
  EXPECT_THROW(Shape::resolve("hexagon"), InputError);
}

// Found by fuzz/fuzz_shape_toml: an infinite radius (or mass, inertia, vertex) was accepted, and
// a length of the wrong type was silently 0. Errors name the file, the key's line and the key.
TEST(Shapes, NonFiniteOrMistypedValuesAreRefusedWithTheirLine) {
  const std::string ok_tail = "mass_kg = 2\ninertia_kgm2 = 0.01\n";
  const struct {
    std::string text;
    std::size_t line;
    std::string field;
  } cases[] = {
      {"vertices = [[0.0, 0.0]]\nrounding_radius_m = +inf\n" + ok_tail, 2, "rounding_radius_m"},
      {"vertices = [[0.0, 0.0]]\nrounding_radius_m = 0.1\nmass_kg = nan\ninertia_kgm2 = 1\n", 3,
       "mass_kg"},
      {"vertices = [\n  [0.0, 0.0],\n  [inf, 0.0]]\nrounding_radius_m = 0.1\n" + ok_tail, 3,
       "vertices"},
      {"vertices = [[0.0, 0.0]]\nrounding_radius_m = 0.1\n" + ok_tail + "length_m = \"long\"\n", 5,
       "length_m"},
      {"vertices = [[0.0, 0.0]]\nrounding_radius_m = 0.1\n" + ok_tail + "length_m = -0.2\n", 5,
       "length_m"},
      {"name = 3\nvertices = [[0.0, 0.0]]\nrounding_radius_m = 0.1\n" + ok_tail, 1, "name"},
  };
  for (const auto& c : cases) {
    try {
      Shape::from_toml_string(c.text, "bad.toml");
      ADD_FAILURE() << c.text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "bad.toml") << c.text;
      EXPECT_EQ(e.line(), c.line) << c.text;
      EXPECT_EQ(e.field(), c.field) << c.text;
    }
  }
}

}  // namespace
}  // namespace ricochet
