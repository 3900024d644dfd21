// The independent simulator itself (truth_sim.hpp), checked against physics rather than against
// the engine it is meant to test: restitution of a frictionless drop, no energy creation, the
// hidden effects vanishing at zero strength, reproducible sets; and that it is a different code
// from the engine (close to it, not equal).
#include <gtest/gtest.h>

#include <cmath>

#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "truth_sim.hpp"

namespace ricochet::truth {
namespace {

double energy(const std::array<double, 3>& v) {
  return 0.5 * 13.9 * (v[0] * v[0] + v[1] * v[1]) + 0.5 * 0.0445 * v[2] * v[2];
}

TEST(TruthSim, FrictionlessDropReturnsTheRestitution) {
  for (double en2 : {0.05, 0.16, 0.5}) {
    const Rebound r = collide({0.0, -2.3, 0.0}, {en2, 0.0, 0.0});
    ASSERT_TRUE(r.ok);
    // Energy restitution e_n^2 (notes) with gravity's work over the penetration h_max:
    // 1/2 kn h^2 = E_in + m g h stores, en2 of it returns, m g h is lost again on the way out.
    const double m = 13.9, g = 9.81, kn = 3e7, e_in = 0.5 * m * 2.3 * 2.3;
    const double h = (m * g + std::sqrt(m * g * m * g + 2 * kn * e_in)) / kn;
    const double e_out = en2 * (e_in + m * g * h) - m * g * h;
    EXPECT_NEAR(r.vout[1], std::sqrt(2 * e_out / m), 0.005 * std::sqrt(2 * e_out / m)) << en2;
    EXPECT_NEAR(r.vout[1] / 2.3, std::sqrt(en2), 0.06 * std::sqrt(en2)) << en2;
    EXPECT_NEAR(r.vout[0], 0.0, 1e-12);
  }
}

TEST(TruthSim, NoEffectCreatesEnergy) {
  for (const auto& name : family_names()) {
    const Family f = family_from_name(name);
    for (const std::array<double, 3> vin :
         {std::array<double, 3>{2.9, -2.3, -65.0}, std::array<double, 3>{5.5, -1.5, -10.0},
          std::array<double, 3>{1.5, -4.5, -90.0}}) {
      const Rebound r = collide(vin, {0.2, 0.4, 0.2, f, 2.0});
      ASSERT_TRUE(r.ok) << name;
      EXPECT_LT(energy(r.vout), energy(vin)) << name;
    }
  }
}

TEST(TruthSim, HiddenEffectsVanishAtZeroStrength) {
  const std::array<double, 3> vin{2.9, -2.3, -65.0};
  const Rebound null = collide(vin, {0.16, 0.35, 0.16});
  for (const auto& name : family_names()) {
    const Rebound r = collide(vin, {0.16, 0.35, 0.16, family_from_name(name), 0.0});
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r.vout[k], null.vout[k]) << name;
    if (name != "none") {
      const Rebound s = collide(vin, {0.16, 0.35, 0.16, family_from_name(name), 1.0});
      double d = 0;
      for (int k = 0; k < 3; ++k) d += std::fabs(s.vout[k] - null.vout[k]);
      EXPECT_GT(d, 0.0) << name;
    }
  }
}

// Another code, not a copy: the same law and parameters give close but different rebounds
// (other integrator, time step and stiffness).
TEST(TruthSim, IsAnotherImplementationOfTheSameLaw) {
  Model m = Model::paper();
  m.set("en2", 0.16);
  m.set("mu", 0.35);
  m.set("muR", 0.16);
  const std::array<double, 3> vin{2.9, -2.3, -65.0};
  const auto e = simulate(m, Shape::cylinder(), {{vin[0], vin[1], vin[2]}, 0.0});
  const Rebound r = collide(vin, {0.16, 0.35, 0.16});
  const double scale[3] = {0.1, 0.1, 3.4};  // the lab's Table 1 scale
  double differs = 0;
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(std::fabs(e.vout[k] - r.vout[k]), 2.0 * scale[k]) << k;
    differs += std::fabs(e.vout[k] - r.vout[k]);
  }
  EXPECT_GT(differs, 1e-3);
}

TEST(TruthSim, SetsAreReproducibleAndCarryNoTruth) {
  SetOptions o;
  o.family = Family::kSpinRolling;
  o.design = Design::kWide;
  o.n = 12;
  o.seed = 5;
  const TruthSet a = make_set(o), b = make_set(o);
  ASSERT_EQ(a.set.size(), 12u);
  for (std::size_t i = 0; i < a.set.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.set.impacts[i].vout[k], b.set.impacts[i].vout[k]);
  o.seed = 6;
  EXPECT_NE(make_set(o).set.impacts[0].vout[0], a.set.impacts[0].vout[0]);
  for (const auto& im : a.set.impacts) {
    EXPECT_FALSE(im.sigma_vout.has_value());
    EXPECT_FALSE(im.penetration.has_value());
  }
  EXPECT_GT(std::fabs(a.mean_shift[2]), 0.0);
  EXPECT_THROW(family_from_name("wind"), std::invalid_argument);
}

TEST(TruthSim, FamilyNamesMapToCandidates) {
  EXPECT_TRUE(names_family(Family::kSpinRolling, "muR_spin_linear"));
  EXPECT_FALSE(names_family(Family::kSpinRolling, "mu_spin_linear"));
  EXPECT_TRUE(names_family(Family::kCrspRestitution, "en2_approach_speed_power"));
  EXPECT_TRUE(names_family(Family::kCrspRestitution, "ploughing+rate_restitution"));
  EXPECT_FALSE(names_family(Family::kNone, "rate_restitution"));
}

}  // namespace
}  // namespace ricochet::truth
