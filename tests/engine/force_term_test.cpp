// The force terms as effects (effects/force_term.hpp): each term's force at a contact state
// against its formula written here by hand, the unilateral normal force, the sign bounds, the
// added stiffness in the critical time step, the model-file round trip and the registry's
// handling of the family. The data-driven references and physical trends are in
// tests/engine/effects/force_term.toml (effect_cases_test.cpp); the registry-wide invariants
// (energy included) in effects_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "effects/force_term.hpp"
#include "effects/model.hpp"
#include "effects/registry.hpp"
#include "engine/engine.hpp"

namespace ricochet {
namespace {

// One lane at a chosen contact state; the law's force before the term is `fn0`, `ft0`, `m0`.
struct OneLane {
  double active = 1, h = 4e-3, dh = 1e-6, vn = -2.0, vt = 0.5, w = -30.0, lever = 0.08, vx = 3.0,
         vy = -2.0;
  double kf = 1, ef = 1, enf = 1, muf = 1, murf = 1;
  double fn = 500.0, ft = -100.0, moment = 20.0, fxb = 7.0, fyb = 0;
  ContactBatch batch() {
    ContactBatch c;
    c.n = 1;
    c.dt = 1e-5;
    c.active = &active;
    c.h = &h;
    c.dh = &dh;
    c.vn = &vn;
    c.vt = &vt;
    c.w = &w;
    c.lever = &lever;
    c.vx = &vx;
    c.vy = &vy;
    c.mass = 13.9;
    c.length = 0.29;
    c.kn_factor = &kf;
    c.elastic_factor = &ef;
    c.en2_factor = &enf;
    c.mu_factor = &muf;
    c.muR_factor = &murf;
    c.fn = &fn;
    c.ft = &ft;
    c.moment = &moment;
    c.fx_body = &fxb;
    c.fy_body = &fyb;
    return c;
  }
};

// The change each term makes at OneLane's state with coefficient c, written from the table of
// docs/effects/force_term.md (h = 4 mm, v_n = -2 m/s loading, v_t = 0.5, v_x = 3 m/s,
// omega = -30 rad/s): 0 normal, 1 tangential, 2 moment, 3 the body force along x.
struct Expected {
  const char* name;
  int component;
  double per_c;
};
const Expected kExpected[] = {
    {"spring", 0, 4e-3},
    {"hertz", 0, 2.5298221281347035e-4},  // 0.004^1.5
    {"quadratic_depth", 0, 1.6e-5},
    {"inertial_drag", 0, 4.0},   // -(-2)|-2|
    {"viscous", 0, 2.0},         // -(-2)
    {"depth_drag", 0, 1.6e-2},   // 0.004 * 4
    {"branch_spring", 0, 4e-3},  // loading: +h
    {"ploughing", 3, -1.6e-5},   // -sign(3) h^2, at the centre (fx_body)
    {"depth_friction_force", 1, -4e-3},
    {"tangential_viscous", 1, -0.5},
    {"tangential_drag", 1, -0.25},
    {"depth_rolling", 2, 4e-3},    // -sign(-30) h
    {"rolling_viscous", 2, 30.0},  // -(-30)
};

TEST(ForceTerm, EachTermAddsItsFormulaAtAContactState) {
  const auto registry = EffectRegistry::with_builtins();
  ASSERT_EQ(effects::force_terms().size(), std::size(kExpected));
  for (const Expected& e : kExpected) {
    const Effect& eff = registry.get("term_" + std::string(e.name));
    ASSERT_EQ(eff.parameters().size(), 1u) << e.name;
    EXPECT_EQ(eff.parameters()[0].name, "c_" + std::string(e.name));
    const double c = 0.5 * eff.parameters()[0].upper;
    OneLane lane;
    ContactBatch b = lane.batch();
    const double* params[] = {&c};
    eff.apply(b, params, nullptr);
    const double got[4] = {lane.fn - 500.0, lane.ft + 100.0, lane.moment - 20.0, lane.fxb - 7.0};
    for (int k = 0; k < 4; ++k) {
      const double want = k == e.component ? c * e.per_c : 0.0;
      EXPECT_NEAR(got[k], want, 1e-9 * (1.0 + std::abs(want))) << e.name << " component " << k;
    }
  }
}

TEST(ForceTerm, TheNormalForceStaysUnilateralAndNothingActsOutOfContact) {
  const auto registry = EffectRegistry::with_builtins();
  const Effect& spring = registry.get("term_spring");
  const double c = spring.parameters()[0].lower;  // a softening as strong as allowed
  ASSERT_LT(c * 4e-3, -500.0) << "the test needs a term that would pull the block in";
  OneLane lane;
  ContactBatch b = lane.batch();
  const double* params[] = {&c};
  spring.apply(b, params, nullptr);
  EXPECT_EQ(lane.fn, 0.0);
  OneLane off;
  off.active = 0;
  off.fn = 0;
  ContactBatch ob = off.batch();
  const double drag = 100.0;
  const double* dp[] = {&drag};
  registry.get("term_inertial_drag").apply(ob, dp, nullptr);
  EXPECT_EQ(off.fn, 0.0);
}

// Elastic curves take either sign; a drag or a hysteresis only c >= 0 (a negative one makes
// energy); the neutral 0 lies inside and is the nominal.
TEST(ForceTerm, OnlyTheElasticCurvesTakeANegativeCoefficient) {
  const auto registry = EffectRegistry::with_builtins();
  for (const effects::ForceTerm& t : effects::force_terms()) {
    const ParameterSpec& p = registry.get(effects::force_term_effect_name(t)).parameters()[0];
    EXPECT_EQ(p.nominal, 0.0) << t.name;
    EXPECT_EQ(p.neutral, 0.0) << t.name;
    EXPECT_GT(p.upper, 0.0) << t.name;
    if (t.elastic)
      EXPECT_EQ(p.lower, -p.upper) << t.name;
    else
      EXPECT_EQ(p.lower, 0.0) << t.name;
  }
  EXPECT_TRUE(effects::find_force_term("spring")->elastic);
  EXPECT_FALSE(effects::find_force_term("branch_spring")->elastic);
}

// The bound makes each term 3e4 N (moment 2.4e3 N m) at the reference state h = 3 mm,
// |v_n| = 2.5 m/s, |v_t| = |v_x| = 1 m/s, |omega| = 40 rad/s, written out here.
TEST(ForceTerm, BoundsAreTheReferenceForceAtTheReferenceState) {
  const auto bound = [](const char* name) {
    return effects::force_term_bound(*effects::find_force_term(name));
  };
  EXPECT_NEAR(bound("spring"), 3e4 / 3e-3, 1e-3);
  EXPECT_NEAR(bound("inertial_drag"), 3e4 / 6.25, 1e-9);
  EXPECT_NEAR(bound("ploughing"), 3e4 / 9e-6, 1e-1);
  EXPECT_NEAR(bound("rolling_viscous"), 2.4e3 / 40.0, 1e-12);
}

// A stiff elastic term shortens the stable step; a drag does not.
TEST(ForceTerm, ElasticTermsEnterTheCriticalTimeStep) {
  const Shape disc = Shape::cylinder();
  // kr at its lower bound: the paper's stiff rolling spring (1e8 N m/rad on I = 0.0445 kg m^2)
  // sets the step otherwise, and the normal spring would not show.
  Model paper = Model::paper();
  paper.set("kr", paper.lower(paper.index("kr")));
  const double base = critical_time_step(paper, disc, paper.values());
  Model stiff = paper.with_effect("term_quadratic_depth");
  stiff.set("kr", paper.value("kr"));
  stiff.set("c_quadratic_depth", stiff.upper(stiff.index("c_quadratic_depth")));
  const double with_term = critical_time_step(stiff, disc, stiff.values());
  // By hand: the normal spring kn + 2 c h at h = the disc's bounding radius 0.08 m, with the
  // engine's effective mass 1 / (1/m + R^2/I), against the paper's stiffest other spring.
  const double c = stiff.value("c_quadratic_depth");
  const double kn = paper.value("kn");
  const double m_eff = 1.0 / (1.0 / disc.mass_kg + 0.08 * 0.08 / disc.inertia_kgm2);
  const double normal_limit = 2.0 / std::sqrt((kn + 2.0 * c * 0.08) / m_eff);
  ASSERT_LT(normal_limit, 2.0 / std::sqrt(kn / m_eff));
  EXPECT_NEAR(with_term, std::min(base, normal_limit), 1e-12 * base);
  EXPECT_LT(with_term, base) << "the bound's term must be the stiffest spring here";
  Model drag = paper.with_effect("term_inertial_drag");
  drag.set("c_inertial_drag", 1000.0);
  EXPECT_EQ(critical_time_step(drag, disc, drag.values()), base);
}

TEST(ForceTerm, AModelFileCarriesADiscoveredLaw) {
  const Model m = Model::from_toml_string(
      "effects = [\"normal\", \"tangential\", \"rolling\", \"term_inertial_drag\", "
      "\"term_spring\"]\n[parameters]\nc_inertial_drag = 60.0\nc_spring = -2.0e5\n",
      "law.toml");
  EXPECT_EQ(m.value("c_inertial_drag"), 60.0);
  EXPECT_EQ(m.value("c_spring"), -2.0e5);
  const Model back = Model::from_toml_string(m.to_toml(), "back.toml");
  EXPECT_EQ(back.effect_names(), m.effect_names());
  EXPECT_EQ(back.values(), m.values());
  // A drag with a negative coefficient is refused, naming the range.
  EXPECT_THROW(Model::from_toml_string("effects = [\"normal\", \"tangential\", \"rolling\", "
                                       "\"term_viscous\"]\n[parameters]\nc_viscous = -5.0\n",
                                       "bad.toml"),
               std::exception);
}

TEST(ForceTerm, TheRegistryNamesTheFamilyAndDiagnoseLeavesItOut) {
  const auto registry = EffectRegistry::with_builtins();
  try {
    (void)registry.get("term_bogus");
    FAIL() << "an unknown term must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("term_<name> with name in {spring, hertz"),
              std::string::npos)
        << e.what();
  }
  std::size_t terms = 0;
  for (const Effect* e : registry.all()) {
    const bool is_term = e->name().starts_with("term_");
    terms += is_term;
    // crater_ramp and crater_rim, contact geometries added by hand, and bearing_yield, the
    // discovery's lead on the resolved beds, are the other effects left out.
    const bool by_hand =
        e->name() == "crater_ramp" || e->name() == "crater_rim" || e->name() == "bearing_yield";
    EXPECT_EQ(e->default_candidate(), !is_term && !by_hand) << e->name();
  }
  EXPECT_EQ(terms, effects::force_terms().size());
}

}  // namespace
}  // namespace ricochet
