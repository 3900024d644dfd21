// The diagnosis on data with a hidden effect (issue 6): for each effect family of the catalog a
// synthetic set generated with that effect; the diagnosis, which gets only the impact set (read
// back from its file), must rank it first, support it, and adding it must bring the held-out
// error within the noise floor. Also: no false alarm without a hidden effect, two hidden effects
// found by two rounds of the ladder, and the honest limit of an effect invisible in V_out.
//
// These sets are made by the engine that is diagnosed, with the catalog's own forms: an inverse
// crime, kept as a regression test of the machinery on the catalog alone (candidates = the
// hand-written catalog). The honest tests, on truths made by an independent simulator with other
// forms, scatter and the generated laws competing, are in tests/detection/.
//
// Design of every set (docs/diagnosis.md, "Tests"): 40 cylinder releases, wide incident design,
// lab measurement noise (paper Table 1 scale), base parameters en2 = 0.2, mu = 0.4, muR = 0.15
// unless the case says otherwise, seed 11. The magnitudes are those of the detection study where
// detection is reliable (not marginal), so that the tests check the method, not luck.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "diagnosis/diagnose.hpp"
#include "diagnosis/synth.hpp"

namespace ricochet::diagnosis {
namespace {

namespace fs = std::filesystem;

struct HiddenCase {
  std::string name;
  std::vector<std::string> effects;                    // hidden in the truth
  std::vector<std::pair<std::string, double>> values;  // truth parameter values
  NoiseSpec noise = NoiseSpec::lab();
};

std::ostream& operator<<(std::ostream& os, const HiddenCase& c) {
  return os << c.name;
}

// The truth runs, the set goes through a file, and only the file's content comes back.
ImpactSet hidden_set(const HiddenCase& c) {
  Model truth = Model::paper();
  for (const auto& e : c.effects) truth = truth.with_effect(e);
  truth.set("en2", 0.2);
  truth.set("mu", 0.4);
  truth.set("muR", 0.15);
  for (const auto& [name, v] : c.values) truth.set(name, v);
  SynthOptions o;
  o.n = 40;
  o.seed = 11;
  o.design = Design::kWide;
  o.noise = c.noise;
  const auto r = synthesize(truth, Shape::cylinder(), o);
  const fs::path file = fs::temp_directory_path() /
                        ("ricochet-hidden-" + c.name + "-" + std::to_string(::getpid()) + ".csv");
  write_impact_set(r.set, file.string());
  ImpactSet set = read_impact_set(file.string());
  fs::remove(file);
  return set;
}

// The hand-written catalog: registered effects that are neither the paper's law nor generated.
std::vector<std::string> catalog() {
  std::vector<std::string> out;
  const Model paper = Model::paper();
  for (const auto& n : EffectRegistry::global().names())
    if (!paper.has_effect(n) && !EffectRegistry::global().get(n).signature().generated)
      out.push_back(n);
  return out;
}

DiagnoseOptions options() {
  DiagnoseOptions o;
  o.candidates = catalog();
  o.assess.release_intervals = false;  // parameter trends without intervals: faster
  o.progress = false;
  return o;
}

std::string ranking_text(const Diagnosis& d) {
  std::string s;
  for (const auto& c : d.ranking)
    s += c.effect + " (held-out " + std::to_string(c.heldout_error) + ", drop " +
         std::to_string(c.error_drop) + " +- " + std::to_string(c.drop_se) +
         (c.supported ? ", supported" : "") + ")\n";
  return s + d.summary;
}

class HiddenEffect : public ::testing::TestWithParam<HiddenCase> {};

TEST_P(HiddenEffect, RankedFirstSupportedAndBringsTheErrorWithinTheFloor) {
  const HiddenCase& c = GetParam();
  const ImpactSet set = hidden_set(c);
  const Diagnosis d = diagnose(Model::paper(), Shape::cylinder(), set, options());
  ASSERT_FALSE(d.ranking.empty());
  const Candidate& best = d.ranking.front();
  EXPECT_EQ(best.effect, c.effects.front()) << ranking_text(d);
  EXPECT_TRUE(best.supported) << ranking_text(d);
  EXPECT_LT(best.p_holm, 0.05);
  EXPECT_EQ(d.verdict, "missing physics");
  EXPECT_TRUE(best.adequacy.adequate)
      << "held-out " << best.heldout_error << " vs floor " << d.baseline.floor.value.mean;
  EXPECT_LE(best.heldout_error, best.adequacy.threshold);
  // The base model's error is above the candidate's, and the evidence says why in words.
  EXPECT_GT(d.baseline.base.heldout.error.mean, best.heldout_error);
  EXPECT_NE(best.evidence.find("consistent with"), std::string::npos) << best.evidence;
  EXPECT_NE(best.evidence.find("held-out error"), std::string::npos);
  // Every effect of the catalog was tried (and pairs only if one was not enough).
  EXPECT_GE(d.ranking.size(), catalog().size());
}

INSTANTIATE_TEST_SUITE_P(
    EachFamily, HiddenEffect,
    ::testing::Values(
        // kv = 0.5 s/m: at 0.25 the leak-free test gives t = 2.4 and a Holm-adjusted p of
        // 0.096 over the five catalog candidates (40 releases).
        HiddenCase{"rate_restitution", {"rate_restitution"}, {{"kv", 0.5}}},
        HiddenCase{"inertial_drag", {"inertial_drag"}, {{"cd", 2000.0}}},
        HiddenCase{"ploughing", {"ploughing"}, {{"cp", 6e8}}},
        // Friction only acts while the contact slides: with the lab's noise the recalibrated
        // mu absorbs most of a depth-hardening friction; at half the lab's noise and a_mu at
        // its bound it is found (t = 4.3; at a_mu = 1000 the leak-free test gives t = 1.6).
        HiddenCase{"depth_friction",
                   {"depth_friction"},
                   {{"a_mu", 2000.0}, {"mu", 0.05}},
                   NoiseSpec::parse("lab,scale=0.5")},
        // A stiffness law changes the contact, not V_out: the set carries penetration
        // and contact duration as a LIGGGHTS run would (0.1 mm, 0.2 ms).
        HiddenCase{"hertz_stiffness",
                   {"hertz_stiffness"},
                   {{"beta", 1.0}},
                   NoiseSpec::parse("lab,penetration=1e-4,contact_duration=2e-4")}),
    [](const ::testing::TestParamInfo<HiddenCase>& info) { return info.param.name; });

TEST(HiddenEffect, NoHiddenEffectNoFalseAlarm) {
  const ImpactSet set = hidden_set({"none", {}, {}});
  const Diagnosis d = diagnose(Model::paper(), Shape::cylinder(), set, options());
  for (const auto& c : d.ranking) EXPECT_FALSE(c.supported) << ranking_text(d);
  EXPECT_EQ(d.verdict, "adequate") << ranking_text(d);
  EXPECT_NE(d.summary.find("no candidate of"), std::string::npos) << d.summary;
}

TEST(HiddenEffect, StiffnessIsInvisibleInVelocitiesAlone) {
  // The honest limit: without penetration and contact duration the same hidden stiffness law
  // leaves no trace the diagnosis can support.
  const ImpactSet set =
      hidden_set({"hertz_velocities",
                  {"hertz_stiffness"},
                  {{"beta", 1.0}},
                  NoiseSpec::parse("lab,penetration=1e-4,contact_duration=2e-4")});
  DiagnoseOptions o = options();
  o.assess.use_features = false;
  o.candidates = {"hertz_stiffness"};
  const Diagnosis d = diagnose(Model::paper(), Shape::cylinder(), set, o);
  ASSERT_EQ(d.ranking.size(), 1u);
  EXPECT_FALSE(d.ranking.front().supported) << ranking_text(d);
  EXPECT_EQ(d.verdict, "adequate");
}

// kv = 0.5 s/m: at 0.25 the second round's rate law had Holm-adjusted p = 0.10 under the
// leak-free corrected test (it was found by the old paired test, which ignored the splits'
// shared training releases).
TEST(HiddenEffect, TwoHiddenEffectsFoundByTwoRoundsOfTheLadder) {
  const ImpactSet set =
      hidden_set({"two", {"rate_restitution", "ploughing"}, {{"kv", 0.5}, {"cp", 6e8}}});
  DiagnoseOptions o = options();
  o.assess.release_fits = false;
  const Ladder l = auto_ladder(Model::paper(), Shape::cylinder(), set, 3, o);
  ASSERT_GE(l.rungs.size(), 3u) << l.stop_reason;
  std::vector<std::string> found = {l.rungs[1].added, l.rungs[2].added};
  std::sort(found.begin(), found.end());
  EXPECT_EQ(found, (std::vector<std::string>{"ploughing", "rate_restitution"}));
  // The error falls at each rung and ends within the noise floor.
  EXPECT_LT(l.rungs[1].assessment.heldout.error.mean, l.rungs[0].assessment.heldout.error.mean);
  EXPECT_LT(l.rungs[2].assessment.heldout.error.mean, l.rungs[1].assessment.heldout.error.mean);
  EXPECT_TRUE(l.rungs[2].adequacy.adequate);
  EXPECT_FALSE(l.rungs[0].adequacy.adequate);
  EXPECT_EQ(l.rungs.size(), 3u) << "a third effect was added: " << l.rungs.back().added;
}

}  // namespace
}  // namespace ricochet::diagnosis
