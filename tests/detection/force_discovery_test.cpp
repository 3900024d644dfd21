// The force-residual discovery (diagnosis/force_law.hpp) on the independent simulator's time
// series (truth_sim.hpp: another integrator, step and stiffness than the engine's), issue 33
// item 4's first cut. The residual is the hidden law's additive force along each release's own
// path (TraceSample::hidden_*), what a perfect model of the paper's law would leave, plus white
// force noise of sd 50 N (an assumption: about 0.1 % of the ~50 kN peak contact force, not a
// measured track noise). The hidden forms are not the library's exact terms: the
// Katsuragi-Durian and depth-speed drags act only while the block penetrates (the library's
// drags act both ways). (A first version of the library's ploughing opposed the contact
// point's slip; on these sets it found the Rankine force in 4 of 10, since a back-spinning
// block slips against its motion; it now opposes the centre's velocity, as the catalog's
// `ploughing` effect does.) Recovery is the truth's family among the selected terms; 30 releases on
// the wide design per set, seeds 1-10 (exploration: the rates below are what this first cut gives,
// not tuned).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <set>
#include <string>

#include "diagnosis/force_law.hpp"
#include "diagnosis/force_residual.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "truth_sim.hpp"

namespace ricochet::truth {
namespace {

using diagnosis::ContactSample;
using diagnosis::ReleaseResidual;

constexpr double kForceNoiseN = 50.0;

std::vector<ReleaseResidual> traced_set(Family f, double strength, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> vx(1.5, 6.0), vy(-5.0, -1.0), w(-90.0, 0.0);
  std::normal_distribution<double> noise(0.0, kForceNoiseN);
  std::vector<ReleaseResidual> out;
  for (int i = 0; i < 30; ++i) {
    const std::array<double, 3> vin = {vx(rng), vy(rng), w(rng)};
    std::vector<TraceSample> trace;
    const Ground g{0.16, 0.35, 0.16, f, strength};
    (void)collide(vin, g, Numerics{}, &trace, 100);
    ReleaseResidual r;
    for (const TraceSample& t : trace) {
      ContactSample s;
      s.h_m = t.h_m;
      s.vn_mps = t.vn_mps;
      s.vt_mps = t.vt_mps;
      s.vx_mps = t.vx_mps;
      s.omega_radps = t.omega_radps;
      s.loading = t.loading;
      r.samples.push_back(s);
      r.residual.push_back({t.hidden_fn_N + noise(rng), t.hidden_ft_N + noise(rng), NAN});
    }
    out.push_back(std::move(r));
  }
  return out;
}

// The user's path: the truth's measured history (PathSample: its path from before the contact
// and its total contact force, each component with the same 50 N noise; the torque is left out) minus the reduced engine's paper law evaluated
// along that path (engine/path_force.hpp, diagnosis/force_residual.hpp) at the truth's base
// parameters and stiffnesses, as a well-calibrated base model would have them. The residual is
// then the hidden force plus what the two implementations do differently: this code integrates
// at 2 us by semi-implicit Euler, the path evaluation steps the tangential and rolling springs
// with the records' 0.2 ms spacing.
std::vector<ReleaseResidual> traced_set_through_law(Family f, double strength, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> vx(1.5, 6.0), vy(-5.0, -1.0), w(-90.0, 0.0);
  std::normal_distribution<double> noise(0.0, kForceNoiseN);
  const Ground g{0.16, 0.35, 0.16, f, strength};
  const Numerics num{};
  Model law = Model::paper();
  law.set("kn", num.kn);
  law.set("kt", num.kt);
  law.set("kr", num.kr);
  law.set("en2", g.en2);
  law.set("mu", g.mu);
  law.set("muR", g.muR);
  const Shape disc = Shape::cylinder();
  std::vector<ReleaseResidual> out;
  for (int i = 0; i < 30; ++i) {
    const std::array<double, 3> vin = {vx(rng), vy(rng), w(rng)};
    std::vector<PathSample> path;
    (void)collide(vin, g, num, nullptr, 100, &path);
    diagnosis::MeasuredHistory h;
    for (const PathSample& p : path) {
      h.path.push_back({p.t_s, p.x_m, p.y_m, p.theta_rad, p.vx_mps, p.vy_mps, p.w_radps});
      h.fx_N.push_back(p.fx_N + noise(rng));
      h.fy_N.push_back(p.fy_N + noise(rng));
      h.torque_Nm.push_back(NAN);
    }
    out.push_back(diagnosis::force_residual(h, law, disc));
    if (std::getenv("PATH_DEBUG") && i == 0) {
      const auto& r = out.back();
      for (std::size_t k = 0; k < r.samples.size(); ++k)
        std::fprintf(stderr, "%zu h=%.5g vn=%.4g load=%d res_n=%.5g res_t=%.5g\n", k,
                     r.samples[k].h_m, r.samples[k].vn_mps, int(r.samples[k].loading),
                     r.residual[k][0], r.residual[k][1]);
    }
  }
  return out;
}

// The selected terms of each component, by name.
std::set<std::string> selected(const std::vector<diagnosis::ComponentLaw>& laws) {
  std::set<std::string> s;
  for (const auto& law : laws)
    for (const auto& t : law.terms)
      if (t.selected) s.insert(std::string(t.term->name));
  return s;
}

struct Case {
  Family family;
  double strength;
  std::set<std::string> family_terms;  // the terms of the truth's family
  std::size_t required;                // of 10 seeds
};

class ForceDiscovery : public ::testing::TestWithParam<Case> {};

TEST_P(ForceDiscovery, TheHiddenForceFamilyIsFound) {
  const Case& c = GetParam();
  std::size_t found = 0;
  std::string laws;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    stats::SparseOptions o;
    o.seed = seed;
    o.bootstrap = 0;
    const auto result = diagnosis::discover_force_law(traced_set(c.family, c.strength, seed), o);
    const auto s = selected(result);
    bool hit = false;
    for (const auto& name : c.family_terms) hit = hit || s.count(name);
    found += hit;
    for (const auto& law : result)
      laws += "seed " + std::to_string(seed) + " " +
              std::string(diagnosis::component_name(law.component)) + ": " + law.text + "\n";
  }
  RecordProperty("found", std::to_string(found));
  EXPECT_GE(found, c.required) << laws;
}

TEST_P(ForceDiscovery, TheHiddenForceFamilyIsFoundThroughTheLawAlongThePath) {
  const Case& c = GetParam();
  std::size_t found = 0;
  std::string laws;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    stats::SparseOptions o;
    o.seed = seed;
    o.bootstrap = 0;
    const auto result =
        diagnosis::discover_force_law(traced_set_through_law(c.family, c.strength, seed), o);
    const auto s = selected(result);
    bool hit = false;
    for (const auto& name : c.family_terms) hit = hit || s.count(name);
    found += hit;
    for (const auto& law : result)
      laws += "seed " + std::to_string(seed) + " " +
              std::string(diagnosis::component_name(law.component)) + ": " + law.text + "\n";
  }
  RecordProperty("found", std::to_string(found));
  EXPECT_GE(found, c.required) << laws;
}

// Strengths: the Katsuragi-Durian drag at its lab scale (m/d1 = 40 kg/m, s = 1); the depth-speed
// drag at s = 1 (40 kg/m at 3 mm); the Rankine ploughing at the wide design's detection-study
// strength (20,568 x the unit-weight reference: c = 1.73e8 N/m^2, 0.69 kN at 2 mm; an earlier
// comment said 1.4 kN, a slip).
INSTANTIATE_TEST_SUITE_P(
    HiddenForces, ForceDiscovery,
    ::testing::Values(Case{Family::kKdDrag, 1.0, {"inertial_drag", "viscous", "depth_drag"}, 8},
                      Case{Family::kDepthSpeedDrag, 1.0, {"depth_drag", "inertial_drag"}, 8},
                      Case{Family::kRankinePlough, 20568.2, {"ploughing"}, 8}),
    [](const ::testing::TestParamInfo<Case>& i) { return family_name(i.param.family); });

// No hidden force: nothing may be found in most sets (the residual is the noise alone).
TEST(ForceDiscoveryNull, NothingIsFoundWithoutAHiddenForce) {
  std::size_t clean = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    stats::SparseOptions o;
    o.seed = seed;
    o.bootstrap = 0;
    clean += selected(diagnosis::discover_force_law(traced_set(Family::kNone, 0, seed), o)).empty();
  }
  RecordProperty("clean", std::to_string(clean));
  EXPECT_GE(clean, 8u);
}

// The same through the law along the path. The two implementations differ by design (truth_sim.hpp:
// integrator, step, lever arm): this code takes the contact point on the ground surface (lever
// R - h), the engine midway in the overlap (R - h / 2), so the slip differs by omega h / 2 and
// the tangential spring with it. Measured on seeds 1-10: the normal law is clean in 10 of 10,
// and the lever difference reads as a ploughing-like tangential term in 6 of 10, c = 3.0e7 to
// 6.2e7 N/m^2, 0.17 to 0.36 of the Rankine case's strength (1.73e8 N/m^2); with the engine's lever
// in this code (a one-line change, tried by hand) nothing is found in 10 of 10. What the test
// holds: the normal component clean in at least 8 of 10, and every term found without a hidden
// force weaker than half the weakest hidden force this file claims to find.
TEST(ForceDiscoveryNull, ThroughTheLawAlongThePathOnlyTheLeverDifferenceIsFound) {
  constexpr double kRankineTestStrength = 20568.2 * 0.5 * 3.7 * 15.7e3 * kLength;  // N/m^2
  std::size_t normal_clean = 0;
  std::string laws;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    stats::SparseOptions o;
    o.seed = seed;
    o.bootstrap = 0;
    const auto result =
        diagnosis::discover_force_law(traced_set_through_law(Family::kNone, 0, seed), o);
    for (const auto& law : result) {
      laws += "seed " + std::to_string(seed) + " " +
              std::string(diagnosis::component_name(law.component)) + ": " + law.text + "\n";
      bool any = false;
      for (const auto& t : law.terms) {
        any = any || t.selected;
        if (t.selected && law.component == diagnosis::ForceComponent::kTangential)
          EXPECT_LT(std::abs(t.coefficient), 0.5 * kRankineTestStrength) << t.term->name;
        if (t.selected && law.component == diagnosis::ForceComponent::kTangential)
          EXPECT_EQ(t.term->name, "ploughing");
      }
      if (law.component == diagnosis::ForceComponent::kNormal) normal_clean += !any;
    }
  }
  RecordProperty("normal_clean", std::to_string(normal_clean));
  EXPECT_GE(normal_clean, 8u) << laws;
}

}  // namespace
}  // namespace ricochet::truth
