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
// lab measurement noise (paper Table 1 scale; penetration 0.5 mm, contact duration 1 ms, or a
// resolved run's 0.1 mm and 0.2 ms where the case says so: kn is calibrated on these features,
// docs/diagnosis.md, "What a free kn does to detection"), base parameters en2 = 0.2, mu = 0.4,
// muR = 0.15 unless the case says otherwise, seed 11. The magnitudes are those of the detection
// study where detection is reliable (not marginal), so that the tests check the method, not luck.
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

// The hand-written catalog that `diagnose` tries by default: registered effects that are neither
// the paper's law nor generated, and not added by hand only (crater_ramp, crater_rim: contact
// geometries for the resolved bed, Effect::default_candidate).
std::vector<std::string> catalog() {
  std::vector<std::string> out;
  const Model paper = Model::paper();
  for (const auto& n : EffectRegistry::global().names()) {
    const Effect& e = EffectRegistry::global().get(n);
    if (!paper.has_effect(n) && !e.generated() && e.default_candidate()) out.push_back(n);
  }
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
        // Penetration and duration at a resolved run's precision (0.1 mm, 0.2 ms), not the lab's
        // 0.5 mm and 1 ms: with kn calibrated on the contact features, a stiffer kn and a lower
        // e_n^2 mimic the drag there (InertialDragAtLabNoiseIsAbsorbedByAFreeKn below).
        HiddenCase{"inertial_drag",
                   {"inertial_drag"},
                   {{"cd", 2000.0}},
                   NoiseSpec::parse("lab,penetration=1e-4,contact_duration=2e-4")},
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
  EXPECT_TRUE(d.baseline.adequacy.adequate) << ranking_text(d);
  EXPECT_NE(d.summary.find("no candidate of"), std::string::npos) << d.summary;
  // Within the floor, `adequate` only with the power to back it (issue 31, 5b): exactly the
  // families whose weakest detectable law needs z > 5 (or none within its bounds) are named.
  ASSERT_FALSE(d.detectable.empty());
  std::vector<Family> blind;
  for (const Detectable& r : d.detectable)
    if (!(r.z_80 <= 5.0)) blind.push_back(r.family);
  EXPECT_EQ(d.underpowered, blind);
  EXPECT_EQ(d.verdict, blind.empty() ? "adequate" : "inconclusive") << d.summary;
  for (Family f : blind)
    EXPECT_NE(d.summary.find(std::string(family_name(f))), std::string::npos) << d.summary;
}

// The honest limit of the contact features at the lab's noise (0.5 mm, 1 ms) once kn is
// calibrated on them (docs/diagnosis.md, "Which stiffnesses the contact features identify"). The
// drag fn = cd vn^2 (cd = 2000 kg/m) against a 13.9 kg cylinder: at max penetration the spring
// holds only 81 % (1 m/s) to 45 % (5 m/s) of the incoming energy, and the penetration is that of
// a drag-free spring of kn_eff = m v^2 / h^2 = 1.2e7 (1 m/s) to 2.2e7 N/m (5 m/s), h = 1.06 to
// 3.96 mm (semi-implicit integration of m h'' = -kn h - cd h'^2, kn = 1e7 N/m). One constant kn
// fitted over 1-5 m/s leaves an rms penetration misfit of 0.19 mm (at most 0.32 mm): below the
// 0.5 mm noise, above the 0.1 mm of the case in EachFamily. So a stiffer kn (for the
// penetration) with a lower e_n^2 (for the dissipated energy, keeping the unloading stiffness
// kn e_n^2 and with it the duration) absorbs the drag: the base model is adequate, and what
// remains is the drag's speed dependence, which 40 releases do not resolve (held-out drop t =
// 2.5, Holm p 0.09; with kn fixed at the truth the base model was 3.4 times its floor).
TEST(HiddenEffect, InertialDragAtLabNoiseIsAbsorbedByAFreeKn) {
  const ImpactSet set = hidden_set({"drag_lab", {"inertial_drag"}, {{"cd", 2000.0}}});
  const Model paper = Model::paper();
  DiagnoseOptions o = options();
  o.assess.release_fits = false;
  const Baseline b = compare(paper, Shape::cylinder(), set, o);
  ASSERT_EQ(b.base.calibrated,
            (std::vector<std::string>{"kn", "en2", "mu", "muR"}));  // kn free: features used
  EXPECT_TRUE(b.adequacy.adequate)
      << "held-out " << b.base.heldout.error.mean << " vs floor " << b.floor.value.mean;
  // The mechanism: kn stiffer than the truth's 1e7 N/m, e_n^2 below the truth's 0.2.
  const std::vector<double>& p = b.base.population.params;
  EXPECT_GT(p[paper.index("kn")], 1.4e7);
  EXPECT_LT(p[paper.index("en2")], 0.15);
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
  // Within the floor, but not `adequate`: the one family tested is the one these data cannot
  // see (issue 31, 5b), and the verdict says so.
  EXPECT_TRUE(d.baseline.adequacy.adequate);
  EXPECT_EQ(d.verdict, "inconclusive") << d.summary;
  EXPECT_EQ(d.underpowered, std::vector<Family>{Family::kStiffness}) << d.summary;
}

// kv = 0.5 s/m: at 0.25 the second round's rate law had Holm-adjusted p = 0.10 under the
// leak-free corrected test (it was found by the old paired test, which ignored the splits'
// shared training releases).
// Penetration and duration at a resolved run's precision (0.1 mm, 0.2 ms). At the lab's 0.5 mm
// and 1 ms, with kn calibrated on them, round 1 added inertial_drag (supported, held-out error
// 1.08 -> 0.69) and round 2 supported nothing: the speed-dependent restitution lengthens the
// unloading at high speed (mean contact 13 ms against 6 ms for the paper's law), the base fit
// softens kn to 6.3e6 N/m for the durations, and drag, which caps the penetration at high speed,
// repairs the penetrations that the soft kn makes too deep (cold fit of paper + drag: kn =
// 3.7e6 N/m, cd = 3150 kg/m). Drag's penetration differs from a constant kn's by 0.2 mm rms
// (InertialDragAtLabNoiseIsAbsorbedByAFreeKn): hidden by 0.5 mm of noise, resolved by 0.1 mm,
// where round 1 finds ploughing and round 2 the rate law. With kn fixed at the truth (before it
// was calibrated) the lab noise sufficed.
TEST(HiddenEffect, TwoHiddenEffectsFoundByTwoRoundsOfTheLadder) {
  const ImpactSet set =
      hidden_set({"two",
                  {"rate_restitution", "ploughing"},
                  {{"kv", 0.5}, {"cp", 6e8}},
                  NoiseSpec::parse("lab,penetration=1e-4,contact_duration=2e-4")});
  DiagnoseOptions o = options();
  o.assess.release_fits = false;
  const Ladder l = auto_ladder(Model::paper(), Shape::cylinder(), set, 3, o);
  std::string rounds;
  for (std::size_t r = 0; r < l.rounds.size(); ++r)
    rounds += "round " + std::to_string(r + 1) + ": " + ranking_text(l.rounds[r]) + "\n";
  ASSERT_GE(l.rungs.size(), 3u) << l.stop_reason << "\n" << rounds;
  std::vector<std::string> found = {l.rungs[1].added, l.rungs[2].added};
  std::sort(found.begin(), found.end());
  EXPECT_EQ(found, (std::vector<std::string>{"ploughing", "rate_restitution"})) << rounds;
  // The error falls at each rung and ends within the noise floor.
  EXPECT_LT(l.rungs[1].assessment.heldout.error.mean, l.rungs[0].assessment.heldout.error.mean);
  EXPECT_LT(l.rungs[2].assessment.heldout.error.mean, l.rungs[1].assessment.heldout.error.mean);
  EXPECT_FALSE(l.rungs[0].adequacy.adequate);
  // Within the floor: judged by the diagnosis of the two-effect model (the last round, whose
  // folds refine the previous round's leak-free fold optima, issue 31 5a: a fold started from
  // the full-set optimum, as before, saw its own held-out releases), not by the warm fit of the
  // rung that added the rate law.
  ASSERT_EQ(l.rounds.size(), 3u) << "a third effect was added: " << l.rungs.back().added;
  EXPECT_TRUE(l.rounds.back().baseline.adequacy.adequate) << rounds;
  EXPECT_NE(l.rounds.back().verdict, "missing physics") << rounds;
  EXPECT_EQ(l.rungs.size(), 3u) << "a third effect was added: " << l.rungs.back().added;
}

// The leak test through the ladder's second round (issue 31, 5a): round 2 diagnoses the model
// calibrated on the whole set in round 1, so its folds would start from values that saw their
// held-out releases. Moving one release's outputs must not move its own held-out prediction in
// round 2 either.
TEST(HiddenEffect, TheLadderSecondRoundDoesNotLeakThroughItsStartValues) {
  const ImpactSet set = hidden_set({"rate_leak", {"rate_restitution"}, {{"kv", 0.5}}});
  ImpactSet moved = set;
  const std::size_t victim = 7;
  // A small change (a fifth of the lab's V_out^x noise): round 1 must add the same effect on
  // both sets for round 2 to be comparable, and a leak shows bit for bit whatever its size.
  moved.impacts[victim].vout[0] += 0.02;
  DiagnoseOptions o = options();
  o.candidates = {"rate_restitution", "ploughing"};
  o.assess.release_fits = false;
  o.assess.repeats = 1;
  const Ladder a = auto_ladder(Model::paper(), Shape::cylinder(), set, 2, o);
  const Ladder b = auto_ladder(Model::paper(), Shape::cylinder(), moved, 2, o);
  ASSERT_GE(a.rounds.size(), 2u) << a.stop_reason;
  ASSERT_GE(b.rounds.size(), 2u) << b.stop_reason;
  ASSERT_EQ(a.rungs[1].added, "rate_restitution");
  ASSERT_EQ(b.rungs[1].added, "rate_restitution");
  // Round 2 starts from different full-set optima (the test can fail) ...
  ASSERT_NE(a.rounds[1].baseline.base.population.params,
            b.rounds[1].baseline.base.population.params);
  // ... and the victim's held-out prediction does not move.
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(a.rounds[1].baseline.base.heldout_predictions[victim].value[k],
              b.rounds[1].baseline.base.heldout_predictions[victim].value[k])
        << "component " << k;
}

// Every diagnosis gives its confidence set of laws (issue 31, item 1): with a strong hidden
// speed-dependent restitution the set holds the restitution family and not the law as it stands;
// with nothing hidden the law as it stands is in it. Every member declares family and variable.
TEST(HiddenEffect, TheConfidenceSetHoldsTheTruthsFamilyAndNotNone) {
  DiagnoseOptions o = options();
  o.candidates.clear();  // the whole registry: catalog and generated laws
  o.assess.release_fits = false;
  o.assess.repeats = 1;
  const Diagnosis d = diagnose(Model::paper(), Shape::cylinder(),
                               hidden_set({"rate_cs", {"rate_restitution"}, {{"kv", 0.5}}}), o);
  const LawConfidenceSet& cs = d.confidence_set;
  ASSERT_FALSE(cs.members.empty()) << d.summary;
  EXPECT_GT(cs.models, 40u);
  EXPECT_FALSE(cs.holds_none()) << d.summary;
  const auto fam = cs.families();
  EXPECT_NE(std::find(fam.begin(), fam.end(), Family::kRestitution), fam.end()) << d.summary;
  for (const LawMember& m : cs.members) {
    if (std::isfinite(m.statistic)) {
      EXPECT_LE(m.gap_to_best, m.critical) << m.effect;
    }
    EXPECT_FALSE(m.law.empty()) << m.effect;
  }
  // Fewer laws than were judged: the set says something.
  EXPECT_LT(cs.members.size(), cs.models) << d.summary;
  const nlohmann::json j = to_json(d);
  ASSERT_TRUE(j.contains("confidence_set"));
  for (const auto& m : j["confidence_set"]) {
    EXPECT_TRUE(m.contains("family") && m.contains("variable") && m.contains("law")) << m.dump();
    EXPECT_NE(m["family"].get<std::string>(), "other") << m.dump();
  }
  EXPECT_NE(d.summary.find("cannot tell apart"), std::string::npos) << d.summary;
  // The second stage (encompassing.hpp) between the families' calibrated laws: the truth's
  // family stays, and every exclusion follows the rule (t_ab > c >= t_ba). Whether any family
  // leaves is a question of power (40 releases: none does here; the closed loop's test,
  // independent_detection_test.cpp, has one that must).
  ASSERT_TRUE(cs.encompassing.has_value()) << d.summary;
  const FamilyEncompassing& e = *cs.encompassing;
  for (std::size_t k = 0; k < e.laws.size(); ++k) {
    if (e.families[k] == Family::kRestitution) {
      EXPECT_LT(e.excluded_by[k], 0) << e.laws[k] << " | " << d.summary;
    }
    if (e.excluded_by[k] >= 0) {
      EXPECT_EQ(std::count(fam.begin(), fam.end(), e.families[k]), 0) << e.laws[k];
      const auto b = static_cast<std::size_t>(e.excluded_by[k]);
      EXPECT_GT(e.t[k][b], e.critical);
      EXPECT_LE(e.t[b][k], e.critical);
    }
  }
  EXPECT_FALSE(j["confidence_set_detail"]["encompassing"].is_null());

  const Diagnosis null =
      diagnose(Model::paper(), Shape::cylinder(), hidden_set({"none_cs", {}, {}}), o);
  EXPECT_TRUE(null.confidence_set.holds_none()) << null.summary;
}

}  // namespace
}  // namespace ricochet::diagnosis
