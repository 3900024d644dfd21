// The generated coefficient laws (effects/coefficient_law.hpp): neutral where they do nothing,
// acting in the physically expected direction, configured from model files, printed as laws.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "common/error.hpp"
#include "effects/coefficient_law.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"

namespace ricochet {
namespace {

const std::filesystem::path kSource(RICOCHET_SOURCE_DIR);

std::vector<std::string> generated() {
  std::vector<std::string> out;
  for (const auto& n : EffectRegistry::global().names())
    if (EffectRegistry::global().get(n).signature().generated) out.push_back(n);
  return out;
}

TEST(CoefficientLaws, TheFamilyIsRegisteredAndDocumented) {
  EXPECT_EQ(generated().size(), 4u * 5u * 2u);
  EXPECT_TRUE(std::filesystem::exists(kSource / "docs/effects/coefficient_law.md"));
  const Effect& e = EffectRegistry::global().get("muR_spin_linear");
  ASSERT_EQ(e.parameters().size(), 1u);
  EXPECT_EQ(e.parameters()[0].name, "c_muR_spin");
  EXPECT_EQ(e.parameters()[0].unit, "s/rad");
  EXPECT_EQ(e.parameters()[0].neutral, 0.0);
  EXPECT_EQ(EffectRegistry::global().get("en2_approach_speed_power").parameters()[0].name,
            "p_en2_vapp");
}

class EachLaw : public ::testing::TestWithParam<std::string> {};

// At its neutral value a law changes nothing, bit for bit (cylinders and triangles, several
// incident states); away from it the rebound changes.
TEST_P(EachLaw, NeutralIsExactlyThePaperLawAndTheLawActsAwayFromIt) {
  const Model paper = Model::paper();
  const Model with = paper.with_effect(GetParam(), /*at_neutral=*/true);
  const std::vector<CollisionCase> cases = {
      {{2.9, -2.3, -65.0}, 0.0}, {{1.5, -4.0, -10.0}, 0.0}, {{5.0, -1.2, -80.0}, 0.0}};
  for (const Shape& shape : {Shape::cylinder(), Shape::triangle()}) {
    std::vector<CollisionCase> cs = cases;
    if (!shape.is_disc())
      for (auto& c : cs) c.alpha_rad = 0.3;
    const auto a = simulate_batch(paper, shape, cs, paper.values());
    const auto b = simulate_batch(with, shape, cs, with.values());
    for (std::size_t i = 0; i < cs.size(); ++i)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(a[i].vout[k], b[i].vout[k]) << GetParam() << " " << k;
  }
  // Away from neutral (a quarter of the way to the upper bound) something changes.
  Model moved = with;
  const ParameterSpec& p = EffectRegistry::global().get(GetParam()).parameters()[0];
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

CollisionResult at_mean(const std::string& law, double value) {
  Model m = Model::paper().with_effect(law, true);
  m.set(EffectRegistry::global().get(law).parameters()[0].name, value);
  return simulate(m, Shape::cylinder(), {{2.9, -2.3, -65.0}, 0.0});
}

// Physics, not regenerated references: restitution that falls with the approach speed lowers
// the rebound, and more at a faster impact; a stiffness growing with depth shortens the contact.
TEST(CoefficientLaws, ActInTheExpectedDirection) {
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
  EXPECT_LT(ratio(-5.0), ratio(-2.0));  // (v0 / 2.5)^-1: below 1 above 2.5 m/s only
  EXPECT_GT(ratio(-2.0), 1.0);
  EXPECT_LT(at_mean("kn_penetration_linear", 1000.0).contact_duration_s,
            at_mean("kn_penetration_linear", 0.0).contact_duration_s);
  EXPECT_LT(at_mean("kn_penetration_linear", 1000.0).max_penetration_m,
            at_mean("kn_penetration_linear", 0.0).max_penetration_m);
  // A rolling resistance growing with spin changes the spin the block leaves with.
  EXPECT_NE(at_mean("muR_spin_linear", 0.02).vout[kW], at_mean("muR_spin_linear", 0.0).vout[kW]);
}

TEST(CoefficientLaws, ModelFileLawTablesAndErrors) {
  const Model m = Model::from_toml_string(
      "effects = [\"normal\", \"tangential\", \"rolling\"]\n"
      "[parameters]\nc_muR_spin = 0.012\n"
      "[[law]]\ncoefficient = \"muR\"\nvariable = \"spin\"\nform = \"linear\"\n",
      "m.toml");
  EXPECT_TRUE(m.has_effect("muR_spin_linear"));
  EXPECT_DOUBLE_EQ(m.value("c_muR_spin"), 0.012);
  // Written back by name with the law in a comment; read back identically.
  const std::string text = m.to_toml();
  EXPECT_NE(text.find("mu_R = mu_R0 (1 + c |omega|), c = 0.012 s/rad"), std::string::npos) << text;
  const Model back = Model::from_toml_string(text, "back.toml");
  EXPECT_EQ(back.effect_names(), m.effect_names());
  EXPECT_EQ(back.values(), m.values());
  // A bad value names the key and lists the accepted ones.
  try {
    (void)Model::from_toml_string(
        "effects = [\"normal\"]\n[[law]]\ncoefficient = \"muR\"\nvariable = \"wind\"\n"
        "form = \"linear\"\n",
        "bad.toml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.toml"), std::string::npos) << what;
    EXPECT_NE(what.find("wind"), std::string::npos) << what;
    EXPECT_NE(what.find("incidence_angle"), std::string::npos) << what;
  }
  // The registry's unknown-name error describes the family instead of listing 40 names.
  try {
    (void)EffectRegistry::global().get("muR_wind_linear");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("rate_restitution"), std::string::npos);
    EXPECT_NE(what.find("<coefficient>_<variable>_<form>"), std::string::npos);
    EXPECT_EQ(what.find("kn_spin_power"), std::string::npos);
  }
}

TEST(CoefficientLaws, LawTextWithNumbersAndUnits) {
  const Effect& lin = EffectRegistry::global().get("muR_spin_linear");
  EXPECT_EQ(lin.law(std::vector<double>{0.012}), "mu_R = mu_R0 (1 + c |omega|), c = 0.012 s/rad");
  const Effect& pw = EffectRegistry::global().get("en2_approach_speed_power");
  EXPECT_EQ(pw.law(std::vector<double>{-0.31}), "e_n^2 = e_n0^2 (v0 / 2.5 m/s)^p, p = -0.31");
}

}  // namespace
}  // namespace ricochet
