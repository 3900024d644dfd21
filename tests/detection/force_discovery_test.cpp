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

#include <cstdint>
#include <random>
#include <set>
#include <string>

#include "diagnosis/force_law.hpp"
#include "force_sets.hpp"

namespace ricochet::truth {
namespace {

struct Case {
  Family family;
  double strength;
  std::set<std::string> family_terms;  // the terms of the truth's family
  std::size_t required;                // of 10 seeds
};

class ForceDiscovery : public ::testing::TestWithParam<Case> {};

TEST_P(ForceDiscovery, TheHiddenForceFamilyIsFound) {
  const Case& c = GetParam();
  std::string laws;
  const std::size_t found =
      sets_finding(traced_set, c.family, c.strength, c.family_terms, 1, 10, &laws);
  RecordProperty("found", std::to_string(found));
  EXPECT_GE(found, c.required) << laws;
}

TEST_P(ForceDiscovery, TheHiddenForceFamilyIsFoundThroughTheLawAlongThePath) {
  const Case& c = GetParam();
  std::string laws;
  const std::size_t found =
      sets_finding(traced_set_through_law, c.family, c.strength, c.family_terms, 1, 10, &laws);
  RecordProperty("found", std::to_string(found));
  EXPECT_GE(found, c.required) << laws;
}

// Below the test's strengths, where the oracle (force_sets.hpp: the exact shape's one coefficient)
// is not far ahead: at the strength where the oracle's mean z is 16 on these seeds, the family is
// still found in 8 of 10 (the power curve on fresh seeds, docs/detection-benchmark.md: 20 of 20
// there, 15-19 of 20 at z = 8, 1-2 at z = 4). The oracle's z is also checked to scale with the
// strength, which the power curve's placement of its levels assumes.
TEST_P(ForceDiscovery, TheFamilyIsFoundWhereTheOraclesZIsSixteen) {
  const Case& c = GetParam();
  const auto mean_z = [&](double strength) {
    double z = 0;
    for (std::uint64_t s = 1; s <= 10; ++s) z += oracle_z(c.family, strength, s) / 10;
    return z;
  };
  const double z1 = mean_z(c.strength);
  ASSERT_GT(z1, 16.0);
  const double strength = c.strength * 16.0 / z1;
  EXPECT_NEAR(mean_z(strength), 16.0, 2.0) << "the oracle's z is not about linear in the strength";
  std::string laws;
  const std::size_t found =
      sets_finding(traced_set, c.family, strength, c.family_terms, 1, 10, &laws);
  RecordProperty("found", std::to_string(found));
  EXPECT_GE(found, 8u) << "at " << strength / c.strength << " x the test strength\n" << laws;
}

// Strengths: the Katsuragi-Durian drag at its lab scale (m/d1 = 40 kg/m, s = 1); the depth-speed
// drag at s = 1 (40 kg/m at 3 mm); the Rankine ploughing at the wide design's detection-study
// strength (20,568 x the unit-weight reference: c = 1.73e8 N/m^2, 0.69 kN at 2 mm; an earlier
// comment said 1.4 kN, a slip).
INSTANTIATE_TEST_SUITE_P(
    HiddenForces, ForceDiscovery,
    ::testing::Values(
        Case{Family::kKdDrag, 1.0, {"inertial_drag", "viscous", "depth_drag"}, 8},
        Case{Family::kDepthSpeedDrag, 1.0, {"depth_drag", "inertial_drag"}, 8},
        Case{Family::kRankinePlough, 20568.2, {"ploughing"}, 8},
        Case{Family::kRateThresholdDrag, 1.0, {"inertial_drag", "viscous", "depth_drag"}, 8}),
    [](const ::testing::TestParamInfo<Case>& i) { return family_name(i.param.family); });

// No hidden force: nothing may be found in most sets (the residual is the noise alone).
TEST(ForceDiscoveryNull, NothingIsFoundWithoutAHiddenForce) {
  std::size_t clean = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed)
    clean += selected_terms(discover(traced_set, Family::kNone, 0, seed)).empty();
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
    for (const auto& law : discover(traced_set_through_law, Family::kNone, 0, seed, &laws)) {
      bool any = false;
      for (const auto& t : law.terms) {
        any = any || t.selected;
        if (t.selected && law.component == diagnosis::ForceComponent::kTangential) {
          EXPECT_LT(std::abs(t.coefficient), 0.5 * kRankineTestStrength) << t.term->name;
          EXPECT_EQ(t.term->name, "ploughing");
        }
      }
      if (law.component == diagnosis::ForceComponent::kNormal) normal_clean += !any;
    }
  }
  RecordProperty("normal_clean", std::to_string(normal_clean));
  EXPECT_GE(normal_clean, 8u) << laws;
}

}  // namespace
}  // namespace ricochet::truth
