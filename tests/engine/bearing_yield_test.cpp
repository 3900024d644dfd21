// The effect `bearing_yield` (effects/bearing_yield.cpp) against its closed forms: a frictionless
// vertical drop without gravity loads along kn h / (1 + h / h_y) and unloads along a straight line,
// so the depth it reaches and the energy it returns follow from the hyperbola's integral alone,
// not from the engine. The neutral value is the paper's law bit for bit.
// Regression references and trends: tests/engine/effects/bearing_yield.toml.
#include <gtest/gtest.h>

#include <cmath>

#include "effects/model.hpp"
#include "engine/engine.hpp"

namespace ricochet {
namespace {

Model frictionless(double inv_hy) {
  Model m = Model::paper().with_effect("bearing_yield", true);
  m.set("mu", 0.0);
  m.set("muR", 0.0);
  m.set("inv_hy", inv_hy);
  return m;
}

CollisionResult drop(const Model& m, double v) {
  EngineOptions o;
  o.gravity_mps2 = 0.0;
  return simulate(m, Shape::cylinder(), {{0.0, -v, 0.0}, 0.0}, {}, o);
}

// x = h_max / h_y. Stored: kn h_y^2 (x - ln(1 + x)) (the hyperbola's integral); returned: the
// unloading line's triangle, e_n^2 kn h_max^2 / (2 (1 + x)).
double returned_share(double en2, double x) {
  return en2 * x * x / (2.0 * (1.0 + x) * (x - std::log1p(x)));
}

TEST(BearingYield, ADropLoadsAlongTheHyperbolaAndReturnsItsShare) {
  const double v = 3.0;
  // The contact's linear stiffness k (the cylinder's slots together) from the neutral drop:
  // 1/2 m v^2 = 1/2 k h0^2.
  const CollisionResult neutral = drop(frictionless(0.0), v);
  ASSERT_EQ(neutral.status, CollisionStatus::kOk);
  const double h0 = neutral.max_penetration_m;
  for (double inv_hy : {100.0, 400.0, 1500.0, 6000.0}) {
    const Model m = frictionless(inv_hy);
    const CollisionResult r = drop(m, v);
    ASSERT_EQ(r.status, CollisionStatus::kOk) << inv_hy;
    // Depth: h0^2 / 2 = h_y^2 (x - ln(1 + x)) at x = h_max / h_y, solved by bisection.
    const double hy = 1.0 / inv_hy;
    double lo = 0.0, hi = 1e3;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (hy * hy * (mid - std::log1p(mid)) < 0.5 * h0 * h0 ? lo : hi) = mid;
    }
    const double x = 0.5 * (lo + hi);
    EXPECT_NEAR(r.max_penetration_m, x * hy, 0.01 * x * hy) << "inv_hy " << inv_hy;
    const double share = r.kinetic_out_J / r.kinetic_in_J;
    EXPECT_NEAR(share, returned_share(m.value("en2"), x), 0.02 * m.value("en2"))
        << "inv_hy " << inv_hy << ", x = " << x;
    // It yields: deeper than the spring, and keeps more than the paper's e_n^2.
    EXPECT_GT(r.max_penetration_m, h0);
    EXPECT_LT(share, m.value("en2"));
  }
}

TEST(BearingYield, NeutralIsThePapersLawBitForBit) {
  const CollisionCase lab{{2.9, -2.3, -65.0}, 0.0};
  for (const Shape& s : {Shape::cylinder(), Shape::triangle()}) {
    const CollisionResult a = simulate(Model::paper(), s, lab);
    const CollisionResult b = simulate(Model::paper().with_effect("bearing_yield", true), s, lab);
    EXPECT_EQ(a.vout, b.vout);
    EXPECT_EQ(a.max_penetration_m, b.max_penetration_m);
    EXPECT_EQ(a.contact_duration_s, b.contact_duration_s);
  }
}

}  // namespace
}  // namespace ricochet
