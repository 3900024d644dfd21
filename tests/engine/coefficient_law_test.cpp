// The generated coefficient laws (effects/coefficient_law.hpp): declared like every effect,
// neutral where they do nothing (bit for bit), acting in the physically expected direction,
// energy-consistent as stiffness laws, configured from model files and printed as laws.
// Regression references of every law: tests/engine/effects/coefficient_law.toml
// (effect_cases_test.cpp); the invariants of every law: effects_test.cpp (whole registry).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>

#include "common/error.hpp"
#include "effects/coefficient_law.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"

namespace ricochet {
namespace {

// The generated coefficient laws (the other generated family, the force terms, has its own test).
std::vector<std::string> generated() {
  std::vector<std::string> out;
  for (const auto& n : EffectRegistry::global().names())
    if (EffectRegistry::global().get(n).generated() && effects::parse_coefficient_law_name(n))
      out.push_back(n);
  return out;
}

const ParameterSpec& param_of(const std::string& law) {
  return EffectRegistry::global().get(law).parameters()[0];
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(CoefficientLaws, EveryCombinationIsRegisteredWithItsDeclarations) {
  EXPECT_EQ(generated().size(), 4u * 5u * 2u);
  const std::map<std::string, std::string> feature = {{"approach_speed", "abs_vin_y"},
                                                      {"slip_speed", "vin_x"},
                                                      {"spin", "win"},
                                                      {"penetration", "penetration"},
                                                      {"incidence_angle", "impact_angle"}};
  std::size_t count = 0;
  for (const auto& variable : effects::law_variable_info())
    for (auto coefficient : effects::law_coefficients())
      for (auto form : effects::law_forms()) {
        const std::string name = effects::coefficient_law_name(coefficient, variable.name, form);
        SCOPED_TRACE(name);
        const Effect& e = EffectRegistry::global().get(name);
        ++count;
        const auto config = effects::parse_coefficient_law_name(name);
        ASSERT_TRUE(config);
        EXPECT_EQ(config->coefficient, coefficient);
        EXPECT_EQ(config->variable, variable.name);
        EXPECT_EQ(config->form, form);
        EXPECT_EQ(e.stage(), Stage::kCoefficient);
        ASSERT_EQ(e.parameters().size(), 1u);
        const ParameterSpec& p = e.parameters()[0];
        EXPECT_EQ(p.name,
                  effects::coefficient_law_parameter_name(coefficient, variable.name, form));
        EXPECT_EQ(p.name, std::string(form == "linear" ? "c_" : "p_") + std::string(coefficient) +
                              "_" + std::string(variable.tag));
        EXPECT_EQ(p.nominal, 0.0);
        EXPECT_EQ(p.neutral, 0.0);
        EXPECT_TRUE(p.calibrated);
        if (form == "linear") {
          EXPECT_DOUBLE_EQ(p.lower, -0.9 / variable.x_hi);
          EXPECT_DOUBLE_EQ(p.upper, 3.0 / variable.x_ref);
        } else {
          EXPECT_EQ(p.unit, "-");
          EXPECT_EQ(p.lower, -1.5);
          EXPECT_EQ(p.upper, 1.5);
        }
        // Held over the contact: the approach speed, the onset angle, and for a stiffness law
        // in h the integral Psi of its loading factor up to the previous step.
        const bool held = variable.name == "approach_speed" || variable.name == "incidence_angle" ||
                          (coefficient == "kn" && variable.name == "penetration");
        EXPECT_EQ(e.state().size(), held ? 1u : 0u);
        const Signature sig = e.signature();
        EXPECT_TRUE(e.generated());
        EXPECT_EQ(sig.contact_bias, coefficient == "kn");
        EXPECT_FALSE(std::string(sig.meaning).empty());
        ASSERT_FALSE(sig.trends.empty());
        // The calibrated coefficient, named by the role of the paper's parameter it multiplies.
        const ExpectedTrend first = parse_trend(sig.trends[0]);
        EXPECT_EQ(first.quantity, TrendQuantity::kParameter);
        EXPECT_EQ(Model::paper().spec(Model::paper().index(coefficient)).role, first.parameter)
            << e.name();
        EXPECT_EQ(sig.trends[0].feature, feature.at(std::string(variable.name)));
        EXPECT_TRUE(contains(std::string(e.reference()), "Brynjarsdottir"));
        EXPECT_FALSE(std::string(e.equation()).empty());
        EXPECT_FALSE(std::string(e.summary()).empty());
      }
  EXPECT_EQ(count, 40u);
  EXPECT_EQ(param_of("muR_spin_linear").unit, "s/rad");
  EXPECT_EQ(param_of("en2_approach_speed_power").name, "p_en2_vapp");
  EXPECT_EQ(param_of("kn_penetration_linear").unit, "1/m");
  // The physics family a law generalises is cited.
  EXPECT_TRUE(
      contains(std::string(EffectRegistry::global().get("en2_approach_speed_linear").reference()),
               "Bourrier"));
  EXPECT_TRUE(contains(
      std::string(EffectRegistry::global().get("mu_penetration_power").reference()), "RAMMS"));
  EXPECT_FALSE(effects::parse_coefficient_law_name("rate_restitution"));
  EXPECT_FALSE(effects::parse_coefficient_law_name("muR_wind_linear"));
}

// A batch of random collisions of both shapes: speeds, spins and (triangle) orientations over
// the lab range and beyond.
std::vector<CollisionCase> random_cases(bool disc, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> vx(-1.0, 6.0), vy(-6.0, -0.8), w(-90.0, 40.0),
      alpha(0.0, 2.0);
  std::vector<CollisionCase> out(24);
  for (auto& c : out) {
    c.vin = {vx(rng), vy(rng), w(rng)};
    c.alpha_rad = disc ? 0.0 : alpha(rng);
  }
  return out;
}

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

class EachLaw : public ::testing::TestWithParam<std::string> {};

// At its neutral value a law changes nothing, bit for bit; away from it the rebound changes.
TEST_P(EachLaw, NeutralIsExactlyThePaperLawAndTheLawActsAwayFromIt) {
  const Model paper = Model::paper();
  const Model with = paper.with_effect(GetParam(), /*at_neutral=*/true);
  for (const Shape& shape : {Shape::cylinder(), Shape::triangle()}) {
    const auto cases = random_cases(shape.is_disc(), shape.is_disc() ? 7u : 11u);
    const auto a = simulate_batch(paper, shape, cases, paper.values());
    const auto b = simulate_batch(with, shape, cases, with.values());
    for (std::size_t i = 0; i < cases.size(); ++i) {
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(bits(a[i].vout[k]), bits(b[i].vout[k])) << shape.name << " case " << i;
      EXPECT_EQ(bits(a[i].contact_duration_s), bits(b[i].contact_duration_s));
      EXPECT_EQ(bits(a[i].max_penetration_m), bits(b[i].max_penetration_m));
      EXPECT_EQ(a[i].status, b[i].status);
      EXPECT_EQ(a[i].contact_phases, b[i].contact_phases);
    }
  }
  // Away from neutral (a quarter of the way to the upper bound) something changes.
  const std::vector<CollisionCase> cases = {
      {{2.9, -2.3, -65.0}, 0.0}, {{1.5, -4.0, -10.0}, 0.0}, {{5.0, -1.2, -80.0}, 0.0}};
  Model moved = with;
  const ParameterSpec& p = param_of(GetParam());
  moved.set(p.name, 0.25 * p.upper);
  const auto a = simulate_batch(paper, Shape::cylinder(), cases, paper.values());
  const auto b = simulate_batch(moved, Shape::cylinder(), cases, moved.values());
  double change = 0;
  for (std::size_t i = 0; i < cases.size(); ++i)
    for (int k = 0; k < 3; ++k) change += std::fabs(a[i].vout[k] - b[i].vout[k]);
  change += std::fabs(a[0].contact_duration_s - b[0].contact_duration_s) * 1e3;
  EXPECT_GT(change, 1e-6) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Generated, EachLaw, ::testing::ValuesIn(generated()),
                         [](const auto& info) { return info.param; });

CollisionResult at_mean(const std::string& law, double value,
                        const Shape& shape = Shape::cylinder()) {
  Model m = Model::paper().with_effect(law, true);
  m.set(param_of(law).name, value);
  return simulate(m, shape, {{2.9, -2.3, -65.0}, 0.0});
}

// Physics, not regenerated references, at the lab mean state (2.9 m/s, -2.3 m/s, -65 rad/s).
TEST(CoefficientLaws, ActInTheExpectedDirection) {
  // A rolling resistance growing with spin takes spin away (|omega_out| falls, monotonically)
  // and so leaves less spin for friction to turn into forward speed (V_out^x falls).
  double w_prev = INFINITY, vx_prev = INFINITY;
  for (double c : {0.0, 0.005, 0.02, 0.075}) {
    const auto r = at_mean("muR_spin_linear", c);
    EXPECT_LT(std::fabs(r.vout[kW]), w_prev) << "c = " << c;
    EXPECT_LT(r.vout[kVx], vx_prev) << "c = " << c;
    w_prev = std::fabs(r.vout[kW]);
    vx_prev = r.vout[kVx];
  }
  // Restitution falling with the approach speed: a lower rebound, more so at a faster impact.
  EXPECT_LT(at_mean("en2_approach_speed_linear", -0.1).vout[kVy],
            at_mean("en2_approach_speed_linear", 0.0).vout[kVy]);
  const Model base = Model::paper();
  Model falling = base.with_effect("en2_approach_speed_power", true);
  falling.set("p_en2_vapp", -1.0);
  auto ratio = [&](double vy) {
    const CollisionCase c{{2.0, vy, 0.0}, 0.0};
    return simulate(falling, Shape::cylinder(), c).vout[kVy] /
           simulate(base, Shape::cylinder(), c).vout[kVy];
  };
  EXPECT_LT(ratio(-5.0), ratio(-3.5));
  EXPECT_LT(ratio(-3.5), 1.0);  // (v0 / 2.5 m/s)^-1: below 1 above 2.5 m/s
  EXPECT_GT(ratio(-2.0), 1.0);  // and above 1 below it
  // A stiffness growing with depth: a shorter, shallower contact.
  EXPECT_LT(at_mean("kn_penetration_linear", 1000.0).contact_duration_s,
            at_mean("kn_penetration_linear", 0.0).contact_duration_s);
  EXPECT_LT(at_mean("kn_penetration_linear", 1000.0).max_penetration_m,
            at_mean("kn_penetration_linear", 0.0).max_penetration_m);
}

// A stiffness law in h unloads along the integral of its loading law: a vertical drop returns
// e_n^2 of the energy stored, less what gravity took (the block leaves at the height where it
// touched, so out/in = e_n^2 - (1 - e_n^2) 2 g h_max / v^2), over the whole range of both forms.
// (The plain (h / x_ref)^p / (1 + p) is infinite or negative for p <= -1 and returned three
// times too much energy at p = -0.9.)
TEST(CoefficientLaws, StiffnessLawsInPenetrationKeepTheEnergyRestitution) {
  const double g = EngineOptions{}.gravity_mps2;
  for (const std::string law : {"kn_penetration_linear", "kn_penetration_power"}) {
    const ParameterSpec& p = param_of(law);
    Model m = Model::paper().with_effect(law, true);
    const double en2 = m.value("en2");
    for (double f : {-1.0, -0.7, -0.3, 0.0, 0.3, 0.7, 1.0}) {
      const double value = f < 0 ? -f * p.lower : f * p.upper;
      m.set(p.name, value);
      for (double v : {1.5, 3.0, 5.0}) {
        const auto r = simulate(m, Shape::cylinder(), {{0.0, -v, 0.0}, 0.0});
        ASSERT_EQ(r.status, CollisionStatus::kOk) << law << " " << value << " v " << v;
        const double out_in = (r.kinetic_out_J + r.potential_change_J) / r.kinetic_in_J;
        const double expected = en2 - (1.0 - en2) * 2.0 * g * r.max_penetration_m / (v * v);
        EXPECT_NEAR(out_in, expected, 0.01 * en2)
            << law << " " << p.name << " = " << value << ", v = " << v;
      }
    }
  }
}

const char* kLawFile =
    "effects = [\"normal\", \"tangential\", \"rolling\"]\n"  // line 1
    "[parameters]\n"                                         // 2
    "c_muR_spin = 0.012\n"                                   // 3
    "[[law]]\n"                                              // 4
    "coefficient = \"muR\"\n"                                // 5
    "variable = \"spin\"\n"                                  // 6
    "form = \"linear\"\n";                                   // 7

TEST(CoefficientLaws, ModelFileLawTablesRoundTrip) {
  const Model m = Model::from_toml_string(kLawFile, "m.toml");
  EXPECT_TRUE(m.has_effect("muR_spin_linear"));
  EXPECT_EQ(
      m.effect_names(),
      Model::from_names({"normal", "tangential", "rolling", "muR_spin_linear"}).effect_names());
  EXPECT_DOUBLE_EQ(m.value("c_muR_spin"), 0.012);
  // Written back as a [[law]] table with the law in a comment, read back identically.
  const std::string text = m.to_toml();
  EXPECT_TRUE(contains(text,
                       "[[law]]\ncoefficient = \"muR\"\nvariable = \"spin\"\n"
                       "form = \"linear\"\n"))
      << text;
  EXPECT_TRUE(contains(text, "# mu_R = mu_R0 (1 + c |omega|), c = 0.012 s/rad\n")) << text;
  EXPECT_FALSE(contains(text, "\"muR_spin_linear\"")) << text;
  const Model back = Model::from_toml_string(text, "back.toml");
  EXPECT_EQ(back.effect_names(), m.effect_names());
  EXPECT_EQ(back.values(), m.values());
  EXPECT_EQ(back.calibrated_indices(), m.calibrated_indices());
  EXPECT_EQ(back.to_toml(), text);

  // Two laws after a hand-written coefficient effect: both tables, in order.
  Model two = Model::from_names({"normal", "tangential", "rolling", "rate_restitution",
                                 "en2_spin_power", "mu_slip_speed_linear"});
  two.set("p_en2_spin", -0.4);
  const std::string two_text = two.to_toml();
  EXPECT_LT(two_text.find("variable = \"spin\""), two_text.find("variable = \"slip_speed\""));
  EXPECT_EQ(Model::from_toml_string(two_text, "two.toml").effect_names(), two.effect_names());
  EXPECT_EQ(Model::from_toml_string(two_text, "two.toml").values(), two.values());

  // A law before a hand-written coefficient effect keeps its name (and so its place, and every
  // bit of the result: the factors multiply in the model's order).
  const Model first =
      Model::from_names({"normal", "tangential", "rolling", "muR_spin_linear", "rate_restitution"});
  const std::string first_text = first.to_toml();
  EXPECT_TRUE(contains(first_text, "\"muR_spin_linear\", \"rate_restitution\"")) << first_text;
  EXPECT_TRUE(contains(first_text, "# muR_spin_linear: mu_R = mu_R0")) << first_text;
  EXPECT_FALSE(contains(first_text, "[[law]]")) << first_text;
  EXPECT_EQ(Model::from_toml_string(first_text, "first.toml").effect_names(), first.effect_names());

  // Names in `effects` keep working, and mix with tables.
  const Model named = Model::from_toml_string(
      "effects = [\"normal\", \"tangential\", \"rolling\", \"kn_spin_linear\"]\n"
      "[[law]]\ncoefficient = \"en2\"\nvariable = \"approach_speed\"\nform = \"power\"\n",
      "named.toml");
  EXPECT_TRUE(named.has_effect("kn_spin_linear"));
  EXPECT_TRUE(named.has_effect("en2_approach_speed_power"));
}

// Each bad [[law]] names the file, the line and the key, and lists the accepted values.
TEST(CoefficientLaws, ModelFileLawErrors) {
  struct Bad {
    std::string from, to;  // replaced in kLawFile
    std::size_t line;
    std::string field, says;
  };
  const std::vector<Bad> bad = {
      {"\"spin\"", "\"wind\"", 6, "law.variable",
       "'wind'; accepted: approach_speed, slip_speed, spin, penetration, incidence_angle"},
      {"\"muR\"", "\"kt\"", 5, "law.coefficient", "'kt'; accepted: kn, en2, mu, muR"},
      {"\"linear\"", "\"quadratic\"", 7, "law.form", "'quadratic'; accepted: linear, power"},
      {"form = \"linear\"", "form = 2", 7, "law.form", "expected a string; accepted: linear"},
      {"form = \"linear\"", "", 4, "law.form", "missing; accepted: linear, power"},
      {"form = \"linear\"", "form = \"linear\"\nexponent = 2", 8, "law.exponent", "unknown key"},
      {"\"rolling\"]", "\"rolling\", \"muR_spin_linear\"]", 4, "law", "already in the model"},
  };
  for (const Bad& b : bad) {
    std::string text = kLawFile;
    text.replace(text.find(b.from), b.from.size(), b.to);
    try {
      (void)Model::from_toml_string(text, "bad.toml");
      ADD_FAILURE() << "no error for " << b.to;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "bad.toml");
      EXPECT_EQ(e.line(), b.line) << e.what();
      EXPECT_EQ(e.field(), b.field) << e.what();
      EXPECT_TRUE(contains(e.what(), b.says)) << e.what();
    }
  }
}

TEST(CoefficientLaws, UnknownNamesListTheAcceptedValues) {
  const auto message = [](const char* c, const char* v, const char* f) {
    try {
      (void)effects::make_coefficient_law(c, v, f);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("kt", "spin", "linear"),
            "unknown coefficient-law coefficient 'kt'; accepted: kn, en2, mu, muR");
  EXPECT_EQ(message("mu", "wind", "linear"),
            "unknown coefficient-law variable 'wind'; accepted: approach_speed, slip_speed, spin, "
            "penetration, incidence_angle");
  EXPECT_EQ(message("mu", "spin", "cubic"),
            "unknown coefficient-law form 'cubic'; accepted: linear, power");
  // The registry's unknown-name error describes the family instead of listing 40 names.
  try {
    (void)EffectRegistry::global().get("muR_wind_linear");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_TRUE(contains(what,
                         "unknown effect 'muR_wind_linear'; known effects: normal, "
                         "tangential, rolling, rate_restitution"))
        << what;
    EXPECT_TRUE(contains(what,
                         "generated coefficient laws <coefficient>_<variable>_<form> with "
                         "coefficient in {kn, en2, mu, muR}, variable in {approach_speed, "
                         "slip_speed, spin, penetration, incidence_angle}, form in "
                         "{linear, power}"))
        << what;
    EXPECT_FALSE(contains(what, "kn_spin_power")) << what;
  }
}

TEST(CoefficientLaws, LawTextWithNumbersAndUnits) {
  const auto law = [](const char* name, double value) {
    return EffectRegistry::global().get(name).law(std::vector<double>{value});
  };
  EXPECT_EQ(law("muR_spin_linear", 0.012), "mu_R = mu_R0 (1 + c |omega|), c = 0.012 s/rad");
  EXPECT_EQ(law("en2_approach_speed_power", -0.31), "e_n^2 = e_n0^2 (v0 / 2.5 m/s)^p, p = -0.31");
  EXPECT_EQ(law("kn_penetration_power", 0.5), "k_n = k_n0 (h / 0.003 m)^p, p = 0.5");
  EXPECT_EQ(law("kn_penetration_linear", 250.0), "k_n = k_n0 (1 + c h), c = 250 1/m");
  EXPECT_EQ(law("mu_incidence_angle_linear", 0.4), "mu = mu0 (1 + c theta_in), c = 0.4 1/rad");
  EXPECT_EQ(law("mu_slip_speed_power", 0.1), "mu = mu0 (|v_t| / 1 m/s)^p, p = 0.1");
}

}  // namespace
}  // namespace ricochet
