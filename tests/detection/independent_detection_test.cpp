// The CI-sized detection benchmark (issue 10, item 5; docs/detection-benchmark.md has the full
// study, scripts/detection-study.sh): impact sets made by the independent simulator
// (truth_sim.hpp: another code, integrator, time step and stiffness; hidden physics in
// non-catalog forms; release-to-release scatter; lab-like noise; velocities only), 40 releases,
// fixed seeds, diagnosed by the built `ricochet` program, which reads only the set's file.
//
// The strengths are chosen from the study (docs/detection-benchmark.md, wide design, 10 seeds
// per cell) where detection is reliable, not where it is marginal, so that a CI failure means
// a broken machine and not bad luck: CRSP restitution at twice its lab-scale strength (the
// strength at which its mean V_out shift reaches the paper's Table 1 scale, 0.1 m/s, 3.4 rad/s;
// lab_scale_strength): found 9 of 10 in the study (10 of 10 at 1.8 x); spin rolling at s = 3 (3 x
// its lab scale; 7 of 10 at 2 x); two effects at s = 10. At the lab scale itself the study finds
// CRSP 2 of 10 and spin rolling 0 of 10 times (data/detection, commit 249c605), against an oracle
// ceiling of 0.54 and 0.88 with a family of 45 candidates: the CI cases check the machinery, the
// study measures power. The design is the wide one (V_in^x 1.5-6 m/s, V_in^y -5 to -1 m/s, omega_in
// -90 to 0 rad/s): on the lab's narrow incident states most of an effect is absorbed by the paper's
// constants.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "support/program_test.hpp"
#include "truth_sim.hpp"

namespace ricochet::truth {
namespace {

using test::quote;

class IndependentDetection : public test::ProgramTest {
 protected:
  static SetOptions options(Family f, double strength, std::uint64_t seed) {
    SetOptions o;
    o.family = f;
    o.strength = strength;
    o.n = 40;
    o.seed = seed;
    o.design = Design::kWide;
    o.refit = false;
    return o;
  }
  // Writes the set and returns its path; the effect size goes to the test's log.
  std::string make(const SetOptions& o) {
    const TruthSet t = make_set(o);
    const std::string path =
        (dir_ / (family_name(o.family) + "-" + std::to_string(o.seed) + ".csv")).string();
    write_impact_set(t.set, path);
    RecordProperty("strength", std::to_string(o.strength));
    RecordProperty("shift_in_lab_units", std::to_string(shift_in_lab_units(t.mean_shift)));
    return path;
  }
  nlohmann::json diagnose(const std::string& path) {
    const auto r = ricochet("diagnose " + quote(path) + " --shape cylinder --json");
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(r.out);
  }
  static std::string ranking_text(const nlohmann::json& d) {
    std::string s = d.value("verdict", "?") + ": ";
    for (const auto& c : d["ranking"])
      s += c.value("effect", "?") + " (score T " + std::to_string(c.value("t", 0.0)) +
           ", max-T p " + std::to_string(c.value("p_adjusted", 1.0)) + ", held-out Holm p " +
           std::to_string(c.value("p_holm", 1.0)) +
           (c.value("supported", false) ? ", supported" : "") + "); ";
    return s;
  }
  static bool top_supported(const nlohmann::json& d) {
    return !d["ranking"].empty() && d["ranking"][0].value("supported", false);
  }
  // (e) The verdict agrees with the ranking (docs/diagnosis.md, "Verdict"): "missing physics"
  // exactly when the top candidate is supported, or none is and Holm-significant trends remain
  // (unnamed_structure, empty whenever a candidate is supported).
  static void expect_consistent(const nlohmann::json& d) {
    const bool top = top_supported(d);
    const bool unnamed = d.contains("unnamed_structure") && !d["unnamed_structure"].empty();
    EXPECT_EQ(d["verdict"] == "missing physics", top || unnamed) << ranking_text(d);
    if (top) {
      EXPECT_FALSE(unnamed) << ranking_text(d);
    }
    // Supported candidates come first in the ranking.
    bool seen_unsupported = false;
    for (const auto& c : d["ranking"]) {
      if (!c.value("supported", false)) seen_unsupported = true;
      if (seen_unsupported) {
        EXPECT_FALSE(c.value("supported", false)) << ranking_text(d);
      }
    }
  }
};

// (a) CRSP-form restitution (2 x the lab scale): the top SUPPORTED candidate is a restitution law.
TEST_F(IndependentDetection, CrspRestitutionIsFoundAsRestitution) {
  SetOptions o = options(Family::kCrspRestitution, 0, 12);
  o.strength = 2.0 * lab_scale_strength(o);
  const auto d = diagnose(make(o));
  ASSERT_FALSE(d["ranking"].empty());
  const auto& best = d["ranking"][0];
  EXPECT_TRUE(best.value("supported", false)) << ranking_text(d);
  EXPECT_EQ(candidate_family(best["effect"]), "restitution") << ranking_text(d);
  expect_consistent(d);
}

// (b) Spin-dependent rolling resistance (no catalog effect has it; s = 3, the lab scale is 1):
// found as a generated law on mu_R and spin, printed with omega.
TEST_F(IndependentDetection, SpinRollingIsPrintedAsALawOnMuRAndSpin) {
  const auto d = diagnose(make(options(Family::kSpinRolling, 3.0, 12)));
  ASSERT_FALSE(d["ranking"].empty());
  const auto& best = d["ranking"][0];
  EXPECT_TRUE(best.value("supported", false)) << ranking_text(d);
  EXPECT_EQ(best.value("effect", "").rfind("muR_spin", 0), 0u) << ranking_text(d);
  const std::string law = best.value("law", "");
  EXPECT_NE(law.find("mu_R"), std::string::npos) << law;
  EXPECT_NE(law.find("omega"), std::string::npos) << law;
  expect_consistent(d);
}

// (c) Null sets (the paper's law with scatter and noise): nothing supported, no false alarm.
TEST_F(IndependentDetection, NothingIsSupportedOnNullSets) {
  for (std::uint64_t seed : {12u, 21u}) {
    const auto d = diagnose(make(options(Family::kNone, 0.0, seed)));
    for (const auto& c : d["ranking"]) {
      EXPECT_FALSE(c.value("supported", false)) << seed << ": " << ranking_text(d);
    }
    EXPECT_NE(d["verdict"], "missing physics") << seed << ": " << ranking_text(d);
    expect_consistent(d);
  }
}

// (f) The measurement floor comes from the set (issue 31, 5b): the simulator's noise is
// 0.05 m/s, 0.03 m/s, 2 rad/s on V_out, 0.5, 0.3 and 0.6 x the paper's Table 1, and the set has
// no uncertainty columns. Without ground scatter the fitted noise must fall below the Table 1
// ceiling on every observable (the fallback used to assume it outright) and the model must not
// be called scattered; with the lab's own ground scatter the same fit must find a spread of
// e_n^2 (the lab's is 0.045 sd) and must not call the model adequate.
TEST_F(IndependentDetection, TheNoiseFloorIsFittedFromTheSet) {
  SetOptions quiet = options(Family::kNone, 0.0, 31);
  quiet.scatter_lo = quiet.scatter_hi = {0.16, 0.35, 0.16};
  const auto q = diagnose(make(quiet));
  EXPECT_EQ(q["noise_floor_source"], "fitted");
  for (const auto& [obs, g] : q["scatter"]["noise_scale_to_table1"].items()) {
    EXPECT_GT(g.get<double>(), 0.15) << obs;
    EXPECT_LT(g.get<double>(), 0.9) << obs;
  }
  EXPECT_NE(q["verdict"], "scatter") << ranking_text(q);
  SetOptions lab = options(Family::kNone, 0.0, 32);
  lab.scatter_lo = kScatterLabLo;
  lab.scatter_hi = kScatterLabHi;
  const auto l = diagnose(make(lab));
  EXPECT_EQ(l["noise_floor_source"], "fitted");
  EXPECT_GT(l["scatter"]["parameters"]["en2"]["sd"].get<double>(), 0.02);
  EXPECT_NE(l["verdict"], "adequate") << ranking_text(l);
}

// (h) A strong effect the diagnosis misses is not called adequate (issue 31, 5b): Rankine
// ploughing at the floor study's strength on the lab's incident states, seeds 8301-8302 of
// scripts/floor-study.sh, where the oracle's z is 9.2 and 7.4 and, before the power gate, the
// verdict was `adequate` (data/detection/floor-study.tsv). Within the fitted floor and nothing
// supported, the verdict must be `inconclusive` and name the families these data could hide.
TEST_F(IndependentDetection, AStrongEffectItMissesIsNotCalledAdequate) {
  for (std::uint64_t seed : {8301, 8302}) {
    SetOptions o = options(Family::kRankinePlough, 82551.6, seed);
    o.design = Design::kLab;
    o.lab_vin = lab_cylinder_states(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
    o.refit = true;  // for the oracle's z
    const TruthSet t = make_set(o);
    ASSERT_GE(t.oracle_z, 5.0) << seed << ": the premise, an effect the oracle sees at z >= 5";
    const std::string path = (dir_ / ("strong-" + std::to_string(seed) + ".csv")).string();
    write_impact_set(t.set, path);
    const auto d = diagnose(path);
    EXPECT_NE(d["verdict"], "adequate") << seed << ": " << ranking_text(d);
    if (d["verdict"] == "inconclusive") {
      EXPECT_FALSE(d["underpowered_families"].empty()) << seed;
      EXPECT_NE(d["summary"].get<std::string>().find("could hide a law of"), std::string::npos)
          << d["summary"];
    }
  }
}

// (g) The closed loop (issue 31, item 4): a hidden spin-dependent rolling resistance on the
// lab's incident states leaves the law as it stands in the confidence set, among several
// families; `ricochet design` plans 40 throws in the wide box from that set; the same truth
// throws them (new ground and noise draws); diagnosed together, the old and new releases must
// remove the law as it stands and shrink the set to the truth's family alone (the issue's
// item 4). Seed 1 of the exploratory closed-loop study (docs/detection-benchmark.md: there the
// set went from 46 laws of 7 families to 3 laws of rolling resistance). How often this happens
// over seeds is the study's table, not this test.
TEST_F(IndependentDetection, TheClosedLoopRemovesTheLawAsItStandsAndKeepsTheTruth) {
  auto families = [](const nlohmann::json& d) {
    std::set<std::string> f;
    for (const auto& m : d["confidence_set"]) f.insert(m["family"].get<std::string>());
    return f;
  };
  SetOptions o = options(Family::kSpinRolling, 2.01086, 1);
  o.design = Design::kLab;
  o.lab_vin = lab_cylinder_states(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
  const TruthSet old_set = make_set(o);
  const std::string old_path = (dir_ / "loop-old.csv").string();
  write_impact_set(old_set.set, old_path);
  const auto before = diagnose(old_path);
  const auto f0 = families(before);
  ASSERT_TRUE(f0.count("none")) << "the loop's premise: the first set cannot reject the law";
  ASSERT_GE(f0.size(), 2u);

  const std::string plan = (dir_ / "plan.csv").string();
  const auto r = ricochet("design " + quote(old_path) +
                          " --shape cylinder --budget 40 --range vin_x=1.5:6 --range "
                          "vin_y=-5:-1 --range win=-90:0 --seed 1 --out " +
                          quote(plan));
  ASSERT_EQ(r.status, 0) << r.err;
  SetOptions thrown = o;
  thrown.design = Design::kGiven;
  for (const auto& im : read_incident_states(plan).impacts) thrown.given_vin.push_back(im.vin);
  thrown.n = thrown.given_vin.size();
  thrown.seed = 100001;
  thrown.id_prefix = "D";
  ImpactSet both = old_set.set;
  for (const auto& im : make_set(thrown).set.impacts) both.impacts.push_back(im);
  const std::string both_path = (dir_ / "loop-both.csv").string();
  write_impact_set(both, both_path);
  const auto after = diagnose(both_path);
  const auto f1 = families(after);
  EXPECT_FALSE(f1.count("none")) << ranking_text(after);
  EXPECT_TRUE(f1.count("rolling_resistance")) << ranking_text(after);
  EXPECT_EQ(f1, std::set<std::string>{"rolling_resistance"}) << ranking_text(after);
  EXPECT_LE(2 * after["confidence_set"].size(), before["confidence_set"].size());
  // The second stage (encompassing.hpp) after the plan: the families' calibrated laws. The
  // truth's family (rolling resistance: the truth's law is muR_spin_linear's form) stays.
  const auto& enc = after["confidence_set_detail"]["encompassing"];
  if (enc.is_object())
    for (const auto& law : enc["laws"])
      if (law["family"] == "rolling_resistance") {
        EXPECT_FALSE(law["excluded"].get<bool>()) << enc.dump();
      }
  RecordProperty("set_before", static_cast<int>(before["confidence_set"].size()));
  RecordProperty("set_after", static_cast<int>(after["confidence_set"].size()));
  RecordProperty("families_after", static_cast<int>(f1.size()));
}

// (g) A law fixed elsewhere (issue 32's fallback: the resolved bed's upscaled law as the base of
// the lab's diagnosis): `--model` with `calibrate = []` keeps the paper's constants where the file
// puts them, here the middle of the truth's ground scatter, and the candidates fit only their own
// parameters. On the spin-rolling set of (b) the missing law is still found on mu_R, the truth's
// law stays in the confidence set, and the base's constants come back unchanged.
TEST_F(IndependentDetection, ALawFixedElsewhereIsDiagnosedWithoutRefittingIt) {
  const std::string model = (dir_ / "fixed-law.toml").string();
  std::ofstream(model) << "effects = [\"normal\", \"tangential\", \"rolling\"]\n"
                          "calibrate = []\n[parameters]\nen2 = 0.16\nmu = 0.35\nmuR = 0.16\n";
  const auto r = ricochet("diagnose " + quote(make(options(Family::kSpinRolling, 3.0, 12))) +
                          " --shape cylinder --model " + quote(model) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto d = nlohmann::json::parse(r.out);
  EXPECT_TRUE(d["base"]["calibrated"].empty());
  EXPECT_DOUBLE_EQ(d["base"]["parameters"]["en2"].get<double>(), 0.16);
  EXPECT_DOUBLE_EQ(d["base"]["parameters"]["mu"].get<double>(), 0.35);
  EXPECT_DOUBLE_EQ(d["base"]["parameters"]["muR"].get<double>(), 0.16);
  ASSERT_FALSE(d["ranking"].empty());
  const auto& best = d["ranking"][0];
  EXPECT_TRUE(best.value("supported", false)) << ranking_text(d);
  // The missing piece is named as rolling resistance; which variable it grows with is not told
  // apart with the base held (seed 12: penetration, approach speed, incidence and spin laws in
  // one confidence set; the constants cannot absorb their common part), the truth's among them.
  bool truth_kept = false;
  for (const auto& c : d["confidence_set"]) {
    truth_kept = truth_kept || c.value("effect", "") == "muR_spin_linear";
  }
  EXPECT_EQ(best["effect"].get<std::string>().rfind("muR_", 0), 0u) << ranking_text(d);
  EXPECT_EQ(d["confidence_set"][0].value("family", ""), "rolling_resistance");
  EXPECT_TRUE(truth_kept) << d["confidence_set"].dump();
  expect_consistent(d);
}

// (d) Two effects at once (CRSP restitution and spin rolling, s = 10 each):
// two rounds of `ladder --auto` name one law of each family (or the first round adds them as a
// pair), and the error falls.
TEST_F(IndependentDetection, TwoEffectsAreNamedInTwoLadderRounds) {
  SetOptions o = options(Family::kTwo, 10.0, 13);
  const std::string path = make(o);
  const auto r = ricochet("ladder " + quote(path) + " --shape cylinder --auto 2 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto l = nlohmann::json::parse(r.out);
  std::string rounds;
  for (const auto& round : l["rounds"]) {
    const nlohmann::json best = round.contains("best") && round["best"].is_object()
                                    ? round["best"]
                                    : nlohmann::json::object();
    rounds += round.value("verdict", "?") + " / " + best.value("effect", "-") +
              (best.value("supported", false) ? " (supported); " : "; ");
    // (e) In every round the verdict agrees with the round's best candidate.
    if (best.value("supported", false)) {
      EXPECT_EQ(round["verdict"], "missing physics") << rounds;
    }
  }
  // Round 1 adds a supported law of one hidden family and round 2 ranks a law of the OTHER
  // family first (whether round 2 also supports it is a question of power; the study,
  // docs/detection-benchmark.md, has the rates), or round 1 adds a supported pair, one law of
  // each family (the pair search: "a+b").
  ASSERT_GE(l["rungs"].size(), 2u) << l.value("stop_reason", "") << " | " << rounds;
  std::set<std::string> families;
  std::stringstream added(l["rungs"][1].value("added", ""));
  for (std::string law; std::getline(added, law, '+');) families.insert(candidate_family(law));
  if (families.size() == 1) {
    ASSERT_GE(l["rounds"].size(), 2u) << rounds;
    families.insert(candidate_family(l["rounds"][1]["best"].value("effect", "")));
  }
  EXPECT_EQ(families, (std::set<std::string>{"restitution", "spin rolling"})) << rounds;
  EXPECT_LT(l["rungs"][1]["heldout_error"].get<double>(),
            l["rungs"][0]["heldout_error"].get<double>());
  if (l["rungs"].size() >= 3) {
    EXPECT_LT(l["rungs"][2]["heldout_error"].get<double>(),
              l["rungs"][1]["heldout_error"].get<double>());
  }
}

}  // namespace
}  // namespace ricochet::truth
