// Physics and determinism of the reduced engine (paper section 4.1, Eq. 3-6).
#include "engine/engine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "common/error.hpp"
#include "engine/effect_checks.hpp"

namespace ricochet {
namespace {

const CollisionCase kLabMean{{2.9, -2.3, -65.0}, 0.0};  // paper section 4.3

// Frictionless vertical drop of the disc: vy_out = -sqrt(e_n^2) vy_in (paper Eq. 4). Gravity is
// switched off: over the 7 ms contact its impulse alone shifts vy_out by ~2 %.
TEST(Engine, FrictionlessDropReturnsSqrtEn2) {
  for (double en2 : {0.02, 0.15, 0.5, 0.9}) {
    Model m = Model::paper();
    m.set("mu", 0.0);
    m.set("muR", 0.0);
    m.set("en2", en2);
    EngineOptions o;
    o.gravity_mps2 = 0.0;
    const double vin = -2.3;
    const auto r = simulate(m, Shape::cylinder(), {{0.0, vin, 0.0}, 0.0}, {}, o);
    EXPECT_EQ(r.status, CollisionStatus::kOk);
    EXPECT_NEAR(r.vout[kVy], -std::sqrt(en2) * vin, 0.005 * std::sqrt(en2) * std::fabs(vin))
        << "en2 = " << en2;
    EXPECT_EQ(r.vout[kVx], 0.0);
    EXPECT_EQ(r.vout[kW], 0.0);
  }
}

// The cost account counts every collision run, one by one or in a batch, and none that a bad
// input refused (ctest runs each test in its own process: no other thread adds meanwhile).
TEST(Engine, CollisionsSimulatedCountsEveryCollisionRun) {
  const Model m = Model::paper();
  const std::uint64_t before = collisions_simulated();
  (void)simulate(m, Shape::cylinder(), kLabMean);
  EXPECT_EQ(collisions_simulated() - before, 1u);
  const std::vector<CollisionCase> cases(7, kLabMean);
  (void)simulate_batch(m, Shape::triangle(), cases);
  EXPECT_EQ(collisions_simulated() - before, 8u);
  EngineOptions bad;
  bad.dt_s = -1.0;
  EXPECT_THROW((void)simulate_batch(m, Shape::cylinder(), cases, {}, bad), InputError);
  EXPECT_EQ(collisions_simulated() - before, 8u);
}

// With gravity the drop still conserves energy exactly up to e_n^2 and the gravity work.
TEST(Engine, DropEnergyBalanceWithGravity) {
  Model m = Model::paper();
  m.set("mu", 0.0);
  m.set("muR", 0.0);
  const auto r = simulate(m, Shape::cylinder(), {{0.0, -2.3, 0.0}, 0.0});
  const double lost = r.kinetic_in_J - r.kinetic_out_J - r.potential_change_J;
  const double accounted = r.dissipated_J[static_cast<int>(Stage::kNormal)];
  EXPECT_NEAR(accounted, lost, 0.01 * r.kinetic_in_J);
}

TEST(Engine, NoFrictionNoSpinKeepsHorizontalVelocity) {
  Model m = Model::paper();
  m.set("mu", 0.0);
  m.set("muR", 0.0);
  for (const Shape& shape : {Shape::cylinder(), Shape::triangle()}) {
    const auto r = simulate(m, shape, {{2.9, -2.3, 0.0}, 0.0});
    EXPECT_EQ(r.vout[kVx], 2.9) << shape.name;
  }
}

// A disc arriving in pure rolling with friction but no rolling resistance: the normal force
// passes through the centre and the contact point barely slides, so it leaves almost as it
// came. Not exactly: the contact point sits mid-overlap, at R - h/2 from the centre, so the
// "rolling" spin -vx/R leaves a slip of vx h / 2R (about 2 %) while the disc is indented.
// Compare with the lab state's sliding contact, which gains 0.4 m/s.
TEST(Engine, PureRollingDiscIsUnchangedTangentially) {
  Model m = Model::paper();
  m.set("mu", 0.5);
  m.set("muR", 0.0);
  const double R = Shape::cylinder().rounding_radius_m;
  const double vx = 2.9, w = -vx / R;
  const auto r = simulate(m, Shape::cylinder(), {{vx, -2.3, w}, 0.0});
  EXPECT_NEAR(r.vout[kVx], vx, 0.02);
  EXPECT_NEAR(r.vout[kW], w, 0.5);
}

// The opposite limit: a sliding disc with a large friction coefficient ends close to rolling
// (slip velocity vx + w R mostly removed), and A_xx > 1 as in the lab (spin converted to speed).
TEST(Engine, HighFrictionDrivesTowardsRolling) {
  Model m = Model::paper();
  m.set("mu", 2.0);
  m.set("muR", 0.0);
  const double R = Shape::cylinder().rounding_radius_m;
  const auto r = simulate(m, Shape::cylinder(), kLabMean);
  const double slip_in = kLabMean.vin[kVx] + kLabMean.vin[kW] * R;
  const double slip_out = r.vout[kVx] + r.vout[kW] * R;
  EXPECT_LT(std::fabs(slip_out), 0.15 * std::fabs(slip_in));
  EXPECT_GT(r.vout[kVx], kLabMean.vin[kVx]);
}

// Halving the step changes V_out by less than 2 mm/s and 0.05 rad/s (far below the lab's
// measurement spread of 0.2 m/s and 6 rad/s, paper Table 1).
TEST(Engine, TimeStepConvergence) {
  const Model m = Model::paper();
  for (const Shape& shape : {Shape::cylinder(), Shape::triangle()}) {
    for (const CollisionCase& c : {kLabMean, CollisionCase{{3.3, -2.2, -40.0}, 0.2}}) {
      EngineOptions coarse, fine;
      coarse.dt_s = 1e-5;
      fine.dt_s = 5e-6;
      const auto a = simulate(m, shape, c, {}, coarse);
      const auto b = simulate(m, shape, c, {}, fine);
      if (a.contact_phases != b.contact_phases) continue;  // a grazing re-contact may flip
      EXPECT_NEAR(a.vout[kVx], b.vout[kVx], 2e-3) << shape.name;
      EXPECT_NEAR(a.vout[kVy], b.vout[kVy], 2e-3) << shape.name;
      EXPECT_NEAR(a.vout[kW], b.vout[kW], 0.05) << shape.name;
    }
  }
}

// The paper's law is dissipative: for random parameters in their bounds and random incident
// states, energy out (kinetic + potential gained) never exceeds energy in, and the stages'
// dissipation accounts for the loss.
TEST(Engine, EnergyNeverIncreases) {
  std::mt19937_64 rng(20201);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Model m = Model::paper();
  for (const Shape& shape : {Shape::cylinder(), Shape::triangle()}) {
    for (int k = 0; k < 60; ++k) {
      std::vector<double> p = m.values();
      p[m.index("en2")] = u(rng);
      p[m.index("mu")] = 2.0 * u(rng);
      p[m.index("muR")] = 2.0 * u(rng);
      const CollisionCase c{{6.0 * u(rng) - 1.0, -0.5 - 4.0 * u(rng), 160.0 * u(rng) - 80.0},
                            2.0 * M_PI * u(rng)};
      const auto r = simulate(m, shape, c, p);
      const double gained = r.kinetic_out_J + r.potential_change_J - r.kinetic_in_J;
      EXPECT_LE(gained, 1e-9 * r.kinetic_in_J) << shape.name << " case " << k;
      double dissipated = 0;
      for (double d : r.dissipated_J) dissipated += d;
      EXPECT_NEAR(dissipated, -gained, 2e-3 * r.kinetic_in_J + 0.01) << shape.name << " " << k;
    }
  }
}

TEST(Engine, ReportsContactFeatures) {
  const auto r = simulate(Model::paper(), Shape::cylinder(), kLabMean);
  EXPECT_EQ(r.status, CollisionStatus::kOk);
  EXPECT_EQ(r.contact_phases, 1);
  // Loading quarter period pi/2 sqrt(m/kn) = 1.85 ms, unloading on the e_n^2 kn spring.
  EXPECT_GT(r.contact_duration_s, 3e-3);
  EXPECT_LT(r.contact_duration_s, 1.2e-2);
  // Penetration of a linear spring: |vy| sqrt(m / kn) = 2.7 mm.
  EXPECT_NEAR(r.max_penetration_m, 2.3 * std::sqrt(13.9 / 1e7), 3e-4);
  EXPECT_GT(r.vout[kVy], 0.0);
}

// A triangle landing corner-first and rotating can touch again with another vertex: the
// rebound then has several phases and ends only when no vertex will come back before the apex.
TEST(Engine, TriangleReContactIsPartOfTheRebound) {
  const Model m = Model::paper();
  int multi = 0;
  for (double a = 0.0; a < 2.0 * M_PI / 3.0; a += 0.05) {
    const auto r = simulate(m, Shape::triangle(), {{3.3, -2.2, -40.0}, a});
    ASSERT_NE(r.status, CollisionStatus::kNoContact);
    if (r.contact_phases > 1) ++multi;
    if (r.status == CollisionStatus::kOk) {
      EXPECT_GT(r.vout[kVy], 0.0);
    }
  }
  EXPECT_GT(multi, 0);
}

TEST(Engine, BatchEqualsSingleBitForBit) {
  const Model m = Model::paper();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const Shape& shape : {Shape::cylinder(), Shape::triangle()}) {
    std::vector<CollisionCase> cases;
    std::vector<double> params;
    for (int k = 0; k < 150; ++k) {
      cases.push_back({{2.0 + u(rng), -1.5 - u(rng), -70.0 + 20.0 * u(rng)}, u(rng)});
      std::vector<double> p = m.values();
      p[m.index("en2")] = 0.05 + 0.2 * u(rng);
      p[m.index("mu")] = 0.6 * u(rng);
      p[m.index("muR")] = 0.3 * u(rng);
      params.insert(params.end(), p.begin(), p.end());
    }
    EngineOptions one, many, wide;
    one.threads = 1;
    one.lanes = 1;
    many.threads = 2;
    many.lanes = 16;
    // 150 cases in one block of 256 lanes: the queue empties at once and the batch narrows
    // (compacts) its lanes as collisions end.
    wide.threads = 1;
    wide.lanes = 256;
    const auto a = simulate_batch(m, shape, cases, params, one);
    const auto b = simulate_batch(m, shape, cases, params, many);
    const auto w = simulate_batch(m, shape, cases, params, wide);
    for (std::size_t k = 0; k < cases.size(); ++k) {
      const std::span<const double> row(params.data() + k * m.parameter_count(),
                                        m.parameter_count());
      const auto c = simulate(m, shape, cases[k], row);
      EXPECT_EQ(a[k].vout, b[k].vout) << k;
      EXPECT_EQ(a[k].vout, w[k].vout) << k;
      EXPECT_EQ(a[k].max_penetration_m, w[k].max_penetration_m) << k;
      EXPECT_EQ(a[k].dissipated_J, w[k].dissipated_J) << k;
      EXPECT_EQ(a[k].vout, c.vout) << k;
      EXPECT_EQ(a[k].contact_duration_s, c.contact_duration_s) << k;
    }
  }
}

// The fused kernel (engine/paper_kernel.hpp) runs every batch whose model holds the paper's law on
// flat ground; a collision with a trace takes the generic path. Both must give the same bits, for
// the paper's law and for every kind of effect the kernel calls through apply(): each stage
// (coefficient, normal, body), a per-contact state, two effects at once. Parameters away from
// their neutral values, so that every effect acts; both shapes.
TEST(Engine, FusedKernelIsTheGenericPathBitForBit) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::vector<std::vector<std::string>> extras = {{},
                                                        {"rate_restitution"},
                                                        {"inertial_drag"},
                                                        {"ploughing"},
                                                        {"depth_friction"},
                                                        {"hertz_stiffness"},
                                                        {"kn_spin_power"},
                                                        {"en2_approach_speed_linear"},
                                                        {"mu_slip_speed_linear"},
                                                        {"muR_penetration_power", "inertial_drag"}};
  for (const Shape& shape : {Shape::cylinder(), Shape::triangle()}) {
    for (const auto& names : extras) {
      Model m = Model::paper();
      for (const auto& n : names) m = m.with_effect(n);
      for (std::size_t i = 0; i < m.parameter_count(); ++i) {
        const ParameterSpec& p = m.spec(i);
        const bool own = p.name != "kn" && p.name != "kt" && p.name != "kr" && p.name != "en2" &&
                         p.name != "mu" && p.name != "muR";
        // Candidates a third of the way from nominal to their upper bound.
        if (own) m.set(p.name, p.nominal + (p.upper - p.nominal) / 3);
      }
      std::vector<CollisionCase> cases;
      for (int k = 0; k < 24; ++k)
        cases.push_back(
            {{0.5 + 4.0 * u(rng), -0.5 - 3.0 * u(rng), -90.0 + 140.0 * u(rng)}, 2.1 * u(rng)});
      EngineOptions options;
      options.max_time_s = 0.1;
      const auto fused = simulate_batch(m, shape, cases, {}, options);
      for (std::size_t k = 0; k < cases.size(); ++k) {
        Trace trace;  // a trace forces the generic path
        const auto generic = simulate(m, shape, cases[k], {}, options, &trace);
        const std::string what = shape.name + " + " + (names.empty() ? "paper" : names[0]);
        EXPECT_EQ(fused[k].vout, generic.vout) << what << " case " << k;
        EXPECT_EQ(fused[k].dissipated_J, generic.dissipated_J) << what << " case " << k;
        EXPECT_EQ(fused[k].max_penetration_m, generic.max_penetration_m) << what;
        EXPECT_EQ(fused[k].contact_duration_s, generic.contact_duration_s) << what;
        EXPECT_EQ(fused[k].contact_phases, generic.contact_phases) << what;
        EXPECT_EQ(fused[k].status, generic.status) << what;
        EXPECT_EQ(fused[k].alpha_out_rad, generic.alpha_out_rad) << what;
      }
    }
  }
}

// A triangle hopping between contact phases flies ballistically; the engine jumps those flights
// by whole steps (EngineOptions::skip_flights). Jumping must give stepping's result up to
// rounding, on both paths (fused kernel, generic with a trace), and must happen (some results
// differ in their last bits).
TEST(Engine, FlightSkipIsSteppingUpToRounding) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Model m = Model::paper();
  std::vector<CollisionCase> cases;
  for (int k = 0; k < 400; ++k)
    cases.push_back(
        {{0.5 + 4.0 * u(rng), -0.5 - 3.0 * u(rng), -100.0 + 150.0 * u(rng)}, 2.1 * u(rng)});
  EngineOptions jump, step;
  jump.max_time_s = step.max_time_s = 0.1;
  step.skip_flights = false;
  const auto a = simulate_batch(m, Shape::triangle(), cases, {}, jump);
  const auto b = simulate_batch(m, Shape::triangle(), cases, {}, step);
  int multi = 0, differ = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    EXPECT_EQ(a[k].status, b[k].status) << k;
    EXPECT_EQ(a[k].contact_phases, b[k].contact_phases) << k;
    for (int c = 0; c < 2; ++c) EXPECT_NEAR(a[k].vout[c], b[k].vout[c], 1e-7) << k;
    EXPECT_NEAR(a[k].vout[kW], b[k].vout[kW], 1e-6) << k;
    EXPECT_NEAR(a[k].contact_duration_s, b[k].contact_duration_s, 1e-9) << k;
    EXPECT_NEAR(a[k].max_penetration_m, b[k].max_penetration_m, 1e-10) << k;
    multi += a[k].contact_phases > 1;
    differ += a[k].vout != b[k].vout;
  }
  EXPECT_GT(multi, 40) << "too few hops to test the jump";
  EXPECT_GT(differ, 0) << "no flight was jumped";
  // The generic path (a trace) jumps the same flights.
  for (std::size_t k = 0; k < 40; ++k) {
    Trace trace;
    EXPECT_EQ(simulate(m, Shape::triangle(), cases[k], {}, jump, &trace).vout, a[k].vout) << k;
  }
}

TEST(Engine, RejectsBadInput) {
  const Model m = Model::paper();
  std::vector<double> p = m.values();
  p[m.index("mu")] = -0.1;
  EXPECT_THROW(simulate(m, Shape::cylinder(), kLabMean, p), std::out_of_range);
  EXPECT_THROW(simulate(m, Shape::cylinder(), kLabMean, std::vector<double>{0.1}),
               std::invalid_argument);
  // Options out of their range are refused by name (EngineOptions::problems), batch or not.
  EngineOptions o;
  o.dt_s = 0;
  try {
    (void)simulate(m, Shape::cylinder(), kLabMean, {}, o);
    ADD_FAILURE() << "simulate accepted dt_s = 0";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "dt_s");
    EXPECT_NE(e.detail().find("outside (0, 0.001)"), std::string::npos) << e.what();
  }
  o.dt_s = EngineOptions::kDt.hi;  // the bound is open
  EXPECT_THROW(
      (void)simulate_batch(m, Shape::cylinder(), std::vector<CollisionCase>{kLabMean}, {}, o),
      InputError);
  o = {};
  o.max_time_s = 0;
  EXPECT_THROW(
      (void)simulate_batch(m, Shape::cylinder(), std::vector<CollisionCase>{kLabMean}, {}, o),
      InputError);
  // The thread count and the lane width are checked by the library, not only by the command line.
  for (const auto& [bad, field] :
       {std::pair{[] { EngineOptions e; e.threads = -1; return e; }(), "threads"},
        std::pair{[] { EngineOptions e; e.lanes = 0; return e; }(), "lanes"}}) {
    try {
      (void)simulate_batch(m, Shape::cylinder(), std::vector<CollisionCase>{kLabMean}, {}, bad);
      ADD_FAILURE() << field << " out of range was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field);
    }
  }
  // A rolling spring too stiff for the step is refused, not integrated into garbage.
  Model stiff = Model::paper();
  stiff.set("kr", 1e10);
  try {
    (void)simulate(stiff, Shape::cylinder(), kLabMean);
    ADD_FAILURE() << "a step beyond the stability limit was integrated";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "dt_s");
    EXPECT_NE(e.detail().find("stability limit"), std::string::npos) << e.what();
  }
  EXPECT_LT(critical_time_step(stiff, Shape::cylinder(), stiff.values()), 1e-5);
  EXPECT_GT(critical_time_step(m, Shape::cylinder(), m.values()), 1e-5);
}

// The stable step reads the springs by role and counts what stiffens them: hertz_stiffness at
// beta = 1 multiplies kn by sqrt(h / h_ref), sqrt(R_b / h_ref) at the deepest penetration
// counted (the bounding radius R_b), and a generated power law of kn by up to its clamp (50).
// The tangential and rolling springs are softened so that the normal one sets the limit, 2 /
// sqrt(factor kn / m_eff) (engine.hpp). A step between the limits with and without the
// stiffening effect is integrated without it and refused with it.
TEST(Engine, CriticalTimeStepCountsWhatStiffensTheContact) {
  const Shape shape = Shape::cylinder();
  const double rb = shape.bounding_radius();
  const double m_eff = 1.0 / (1.0 / shape.mass_kg + rb * rb / shape.inertia_kgm2);
  const auto limit = [&](double factor) { return 2.0 / std::sqrt(factor * 1e7 / m_eff); };
  const auto soft = [](Model m) {
    m.set("kt", 1e5);
    m.set("kr", 1e5);
    return m;
  };
  Model hertz = soft(Model::paper().with_effect("hertz_stiffness", true));
  hertz.set("h_ref", 1e-4);
  const double plain = critical_time_step(hertz, shape, hertz.values());
  hertz.set("beta", 1.0);
  const double stiff = critical_time_step(hertz, shape, hertz.values());
  EXPECT_NEAR(stiff, limit(std::sqrt(rb / 1e-4)), 1e-12 * stiff);
  EXPECT_LT(stiff, 0.5 * plain);
  EngineOptions between;
  between.dt_s = std::sqrt(stiff * plain);
  EXPECT_THROW(simulate(hertz, shape, kLabMean, {}, between), InputError);
  hertz.set("beta", 0.0);
  EXPECT_NO_THROW(simulate(hertz, shape, kLabMean, {}, between));

  Model law = soft(Model::paper().with_effect("kn_penetration_power", true));
  EXPECT_EQ(critical_time_step(law, shape, law.values()), plain);
  law.set("p_kn_h", 1.0);
  EXPECT_NEAR(critical_time_step(law, shape, law.values()), limit(50.0), 1e-12 * limit(50.0));
}

TEST(Engine, TimeoutIsReportedNotHidden) {
  Model m = Model::paper();
  m.set("en2", 0.0);  // no elastic return: the block cannot leave the ground
  EngineOptions o;
  o.max_time_s = 0.05;
  const auto r = simulate(m, Shape::cylinder(), {{0.0, -1.0, 0.0}, 0.0}, {}, o);
  EXPECT_EQ(r.status, CollisionStatus::kNoRebound);
}

TEST(Engine, GroundProfileTiltsTheRebound) {
  // A 10-degree slope rising in +x pushes a vertical drop backwards (-x).
  EngineOptions o;
  o.ground.x_m = {-1.0, 1.0};
  o.ground.y_m = {-std::tan(0.1745), std::tan(0.1745)};
  Model m = Model::paper();
  m.set("mu", 0.0);
  m.set("muR", 0.0);
  const auto r = simulate(m, Shape::cylinder(), {{0.0, -2.3, 0.0}, 0.0}, {}, o);
  EXPECT_EQ(r.status, CollisionStatus::kOk);
  EXPECT_LT(r.vout[kVx], -0.05);
}

}  // namespace
}  // namespace ricochet
