// The synth, compare, diagnose, ladder and report commands run as real programs: JSON
// contracts, files, errors naming the option, the truth kept out of the data, and the HTML
// report rendered in headless Chromium with every figure shown.
#include <gtest/gtest.h>

#include <cmath>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/h5.hpp"
#include "impact/impact_set.hpp"
#include "support/chromium.hpp"
#include "support/program_test.hpp"

namespace ricochet {
namespace {

using test::chromium_missing;
using test::quote;
using test::render_in_chromium;
using test::RenderedFigures;
using test::RunResult;
using test::screenshot;
using test::slurp;
namespace fs = std::filesystem;

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

class CmdDiagnosis : public test::ProgramTest {
 protected:
  // A small synthetic set with a hidden effect, its truth in a separate file.
  std::string make_set(const std::string& name, const std::string& extra = "") {
    const std::string data = (dir_ / (name + ".csv")).string();
    const RunResult r = ricochet(
        "synth --n 14 --seed 5 --design wide --set en2=0.2 --set mu=0.4 --set muR=0.15 "
        "--add rate_restitution --set kv=0.3 --truth " +
        quote((dir_ / (name + ".truth.json")).string()) + " --out " + quote(data) + " " + extra);
    EXPECT_EQ(r.status, 0) << r.err;
    return data;
  }
};

TEST_F(CmdDiagnosis, SynthWritesTheSchemaAndKeepsTheTruthApart) {
  const std::string data = make_set("s", "--json");
  const ImpactSet set = read_impact_set(data);
  ASSERT_EQ(set.size(), 14u);
  for (const auto& im : set.impacts) {
    EXPECT_TRUE(im.sigma_vin && im.sigma_vout && im.penetration && im.contact_duration);
  }
  const std::string bytes = slurp(data);
  EXPECT_EQ(bytes.find("rate_restitution"), std::string::npos);
  EXPECT_EQ(bytes.find("kv"), std::string::npos);
  const auto truth = nlohmann::json::parse(slurp(dir_ / "s.truth.json"));
  EXPECT_NE(truth["model"].dump().find("rate_restitution"), std::string::npos);
  EXPECT_EQ(truth["releases"].size(), 14u);

  // The diagnosis sees only the data: it runs the same with the truth file gone.
  fs::remove(dir_ / "s.truth.json");
  const RunResult d =
      ricochet("diagnose " + quote(data) + " --shape cylinder --no-release-fits --folds 3 --json");
  ASSERT_EQ(d.status, 0) << d.err;
  const auto doc = nlohmann::json::parse(d.out);
  for (const char* key : {"verdict", "noise_floor", "base_error", "ranking", "unexplained"})
    EXPECT_TRUE(doc.contains(key)) << key;
  // The verdict never contradicts the ranking (at least the best candidate is calibrated).
  ASSERT_GE(doc["ranking"].size(), 1u);
  const std::string verdict = doc["verdict"];
  if (doc["ranking"][0]["supported"].get<bool>())
    EXPECT_EQ(verdict, "missing physics");
  else if (verdict == "missing physics")
    EXPECT_FALSE(doc["unnamed_structure"].empty());
  else
    EXPECT_TRUE(verdict == "adequate" || verdict == "inconclusive" || verdict == "scatter")
        << verdict;
  // `adequate` is backed by power (issue 31, 5b): every family's weakest detectable law at
  // z_80 <= adequate_z; otherwise the families that are not are listed.
  bool all_visible = true;
  for (const auto& r : doc["minimum_detectable"])
    all_visible = all_visible && r["z_80"].is_number() &&
                  r["z_80"].get<double>() <= doc["adequate_z"].get<double>();
  // Braced: a gtest macro ends in an `if ... else`, which a bare `if` would capture.
  if (verdict == "adequate") {
    EXPECT_TRUE(all_visible);
  }
  if (verdict == "inconclusive") {
    EXPECT_FALSE(doc["underpowered_families"].empty());
  }
  // The family: every candidate, calibrated (ranking) or only score-tested (screened_out):
  // the 5 catalog effects and the 40 generated laws.
  EXPECT_EQ(doc["family_size"].get<std::size_t>(), 45u);
  EXPECT_EQ(doc["family_size"].get<std::size_t>(),
            doc["ranking"].size() + doc["screened_out"].size());
  for (const auto& c : doc["ranking"])
    for (const char* key : {"effect", "heldout_error", "error_drop", "evidence", "drop_se", "t",
                            "p_value", "p_adjusted", "heldout_t"})
      EXPECT_TRUE(c.contains(key)) << key;
  // Only a candidate with a family-wise adjusted p below alpha / 2 on one of the two routes
  // (score test, held-out test) can be supported, and no adjustment lowers a p-value.
  for (const auto* list : {&doc["ranking"], &doc["screened_out"]})
    for (const auto& c : *list)
      EXPECT_GE(c["p_adjusted"].get<double>(), c["p_value"].get<double>() - 1e-12) << c.dump();
  for (const auto& c : doc["ranking"]) {
    EXPECT_GE(c["p_holm"].get<double>(), c["heldout_p"].get<double>() - 1e-12) << c.dump();
    if (c.value("supported", false)) {
      EXPECT_TRUE(c["p_adjusted"].get<double>() < 0.025 || c["p_holm"].get<double>() < 0.025)
          << c.dump();
      EXPECT_GT(c["error_drop"].get<double>(), 0.0) << c.dump();
    }
  }
  // Best first: supported effects, then by penalised held-out error.
  for (std::size_t i = 1; i < doc["ranking"].size(); ++i) {
    const auto& a = doc["ranking"][i - 1];
    const auto& b = doc["ranking"][i];
    if (a["supported"] == b["supported"] && a["penalised_heldout_error"].is_number() &&
        b["penalised_heldout_error"].is_number()) {
      EXPECT_LE(a["penalised_heldout_error"].get<double>(),
                b["penalised_heldout_error"].get<double>());
    }
  }
}

TEST_F(CmdDiagnosis, CompareReportsPerObservableRegimeAndReleaseWithFigures) {
  const fs::path figs = dir_ / "figs";
  const RunResult r = ricochet("compare " + quote(kLab + "cylinders.csv") +
                               " --no-intervals --folds 4 --json --figures " +
                               quote(figs.string()) + " --out " + quote((dir_ / "c.h5").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["shape"], "cylinder");
  EXPECT_EQ(doc["releases"].size(), 28u);
  // No replicates, no uncertainty columns: the noise is fitted, Table 1 its ceiling (5b).
  EXPECT_EQ(doc["noise_floor"]["source"], "fitted");
  EXPECT_EQ(doc["folds"], 4);
  EXPECT_EQ(doc["regimes"].size(), 3u);
  for (const char* k : {"vx", "vy", "w"}) {
    EXPECT_TRUE(doc["heldout_per_component"].contains(k));
    EXPECT_TRUE(doc["ks"].contains(k));
  }
  EXPECT_FALSE(doc["heldout_per_component"].contains("penetration"));  // the lab has none
  EXPECT_GT(doc["heldout_error"].get<double>(), 0.0);
  ASSERT_TRUE(doc.contains("figures"));
  for (const auto& f : doc["figures"]) {
    const std::string svg = slurp(f.get<std::string>());
    EXPECT_NE(svg.find("<svg"), std::string::npos) << f;
  }
  EXPECT_TRUE(fs::exists(figs / "residuals-vx.svg"));
  EXPECT_TRUE(fs::exists(figs / "parameter-en2.svg"));
  // The HDF5 output holds the compared set and the per-release results.
  const ImpactSet back = read_impact_set((dir_ / "c.h5").string());
  EXPECT_EQ(back.size(), 28u);
  h5::File f((dir_ / "c.h5").string(), h5::File::Mode::kRead);
  EXPECT_EQ(f.read_doubles("/compare/releases/heldout_error").size(), 28u);
}

// The power of every tested law (issue 31, item 2; diagnosis/power.hpp). Within its bounds a
// law's 80 % strength is solved on the engine: the curve t_curve of the statistic's mean holds a
// point at |change_80| at or above critical + 0.8416 and one just below it (the bisection's
// bracket, a factor 2^(1/64)) under it. Beyond its bounds (value null) the curve stays under
// the target up to the bound, and change_80 is the first-order strength
// b a / sqrt(1 + (b a / ceiling)^2) = target, or null when the ceiling lies below the target.
// Each family's row is its candidate of smallest change in noise units among those within
// bounds. Checked on the lab cylinders (nothing detectable within bounds) and on a wide
// synthetic set without any effect (most laws detectable within bounds).
void check_power_rows(const nlohmann::json& doc, std::size_t* within, std::size_t* never) {
  const auto& rows = doc["minimum_detectable_by_candidate"];
  ASSERT_GE(rows.size(), 40u);
  for (const auto& row : rows) {
    const double k = row["critical_value"].get<double>() + 0.8416212335729143;
    const double a = row["t_per_unit"].get<double>();
    const double ceiling = row["t_ceiling"].is_number() ? row["t_ceiling"].get<double>() : 1e300;
    ASSERT_GT(a, 0.0) << row["effect"];
    std::vector<std::pair<double, double>> curve;
    for (const auto& p : row["t_curve"])
      if (p[0].is_number() && p[1].is_number())
        curve.emplace_back(std::fabs(p[0].get<double>()), p[1].get<double>());
    ASSERT_FALSE(curve.empty()) << row["effect"];
    if (row["value"].is_number()) {
      ++*within;
      const double b = std::fabs(row["change_80"].get<double>());
      bool at = false, below = false;
      for (const auto& [x, t] : curve) {
        at = at || (std::fabs(x - b) <= 1e-9 * b && t >= k);
        below = below || (x < b && x >= b / 1.02 && t < k);
      }
      EXPECT_TRUE(at && below) << row["effect"] << ": change_80 " << b;
      EXPECT_EQ(row["law"].get<std::string>().find("not detectable"), std::string::npos)
          << row["effect"];
      continue;
    }
    double top_t = 0, top_x = 0;
    for (const auto& [x, t] : curve)
      if (x >= top_x) top_x = x, top_t = t;
    EXPECT_LT(top_t, k) << row["effect"] << ": reaches the target at its bound";
    EXPECT_NE(row["law"].get<std::string>().find("not detectable within its bounds"),
              std::string::npos)
        << row["effect"];
    if (row["change_80"].is_null()) {
      ++*never;
      EXPECT_LE(ceiling, k) << row["effect"];
      continue;
    }
    const double b = std::fabs(row["change_80"].get<double>());
    const double t = b * a / std::sqrt(1 + (b * a / ceiling) * (b * a / ceiling));
    EXPECT_NEAR(t, k, 1e-6 * k) << row["effect"];
  }
  for (const auto& fam : doc["minimum_detectable"]) {
    bool found = false;
    for (const auto& row : rows) {
      if (row["family"] != fam["family"]) continue;
      found = found || row["effect"] == fam["effect"];
      if (fam["value"].is_number() && row["value"].is_number()) {
        EXPECT_LE(fam["noise_units"].get<double>(), row["noise_units"].get<double>() + 1e-12)
            << fam["family"] << ": " << row["effect"];
      }
    }
    EXPECT_TRUE(found) << fam["family"];
  }
}

TEST_F(CmdDiagnosis, ThePowerOfEveryLawIsSolvedOnTheEngineWithinItsBounds) {
  std::size_t within = 0, never = 0;
  const RunResult r = ricochet("diagnose " + quote(kLab + "cylinders.csv") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json doc = nlohmann::json::parse(r.out);
  check_power_rows(doc, &within, &never);
  EXPECT_EQ(within, 0u);  // 28 lab releases: no law reaches 80 % power within its bounds
  // The cost account (docs/performance.md reads it): the phases add up to the whole, the base
  // model's assessment is part of the baseline, and the power curves ran on the engine.
  std::uint64_t phases = 0;
  for (const auto& [phase, n] : doc.at("collisions_by_phase").items())
    phases += n.get<std::uint64_t>();
  EXPECT_EQ(phases, doc.at("collisions").get<std::uint64_t>());
  EXPECT_GT(doc.at("base").at("collisions").get<std::uint64_t>(), 0u);
  EXPECT_LE(doc.at("base").at("collisions").get<std::uint64_t>(),
            doc.at("collisions_by_phase").at("baseline").get<std::uint64_t>());
  EXPECT_GT(doc.at("collisions_by_phase").at("power").get<std::uint64_t>(), 0u);
  const std::string wide = (dir_ / "wide-null.csv").string();
  const RunResult s = ricochet("synth --n 40 --seed 8 --design wide --out " + quote(wide));
  ASSERT_EQ(s.status, 0) << s.err;
  const RunResult w = ricochet("diagnose " + quote(wide) + " --json");
  ASSERT_EQ(w.status, 0) << w.err;
  std::size_t wide_within = 0;
  check_power_rows(nlohmann::json::parse(w.out), &wide_within, &never);
  EXPECT_GE(wide_within, 10u);  // 40 releases across the box: many laws within their bounds
  RecordProperty("laws_never_at_80_percent", static_cast<int>(never));
}

TEST_F(CmdDiagnosis, LadderContract) {
  const std::string data = make_set("l");
  const RunResult r = ricochet("ladder " + quote(data) +
                               " --shape cylinder --add rate_restitution --add ploughing "
                               "--folds 3 --json --out " +
                               quote((dir_ / "l.csv").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["rungs"].size(), 3u);
  EXPECT_EQ(doc["rungs"][0]["model"],
            (std::vector<std::string>{"normal", "tangential", "rolling"}));
  EXPECT_EQ(doc["rungs"][1]["added"], "rate_restitution");
  for (const auto& rung : doc["rungs"]) {
    EXPECT_TRUE(rung["insample_error"].is_number());
    EXPECT_TRUE(rung["heldout_error"].is_number());
    EXPECT_TRUE(rung["heldout_per_component"].contains("vy"));
  }
  // The hidden speed-dependent restitution makes the error fall at rung 1.
  EXPECT_LT(doc["rungs"][1]["heldout_error"].get<double>(),
            doc["rungs"][0]["heldout_error"].get<double>());
  const std::string csv = slurp(dir_ / "l.csv");
  EXPECT_NE(csv.find("rung,added,model,insample_error,heldout_error"), std::string::npos);
}

// The rim on the stiff resolved bed (docs/diagnosis.md, "Added: the rim"): the sand-only
// recalibration's 27 rebounds, whose blocks roll out of their craters above the level. Added by
// hand, crater_rim takes the held-out error down by more than two standard errors of the base
// rung, mostly in the contact duration, where crater_ramp (flat ground) moved it by under 1 %.
TEST_F(CmdDiagnosis, TheRimLowersTheStiffBedsHeldOutError) {
  const std::string resolved =
      std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/sand-verification-1.5e9.h5";
  const RunResult r = ricochet("ladder " + quote(resolved) + " --add crater_rim --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["rungs"].size(), 2u);
  const auto& base = doc["rungs"][0];
  const auto& rim = doc["rungs"][1];
  EXPECT_EQ(rim["added"], "crater_rim");
  EXPECT_LT(rim["heldout_error"].get<double>(),
            base["heldout_error"].get<double>() - 2 * base["heldout_se"].get<double>())
      << r.out.substr(0, 3000);
  EXPECT_LT(rim["heldout_per_component"]["contact_duration"].get<double>(),
            0.75 * base["heldout_per_component"]["contact_duration"].get<double>());
}

// The force histories' floor (issue 33, item 4): the verification has one bed position per
// state, so its ladder reads the force-history error against the replicate histories of the file
// whose V_out scatter it borrows (--floor-replicates: the calibration's position pairs), says
// where the floor comes from, and gives none without it. The floor's arithmetic is
// ForceHistoryFloor's (hand-made histories); here, that it is read from the file named.
TEST_F(CmdDiagnosis, TheLadderReadsTheForceHistoriesAgainstTheirReplicateFloor) {
  const std::string dir = std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/";
  const std::string resolved = dir + "sand-verification-1.5e9.h5";
  const std::string pairs = dir + "sand-calibration-1.5e9.h5";
  const RunResult r = ricochet("ladder " + quote(resolved) +
                               " --add crater_rim --floor-replicates " + quote(pairs) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_TRUE(doc.contains("force_history_floor")) << r.out.substr(0, 2000);
  const auto& floor = doc["force_history_floor"];
  EXPECT_EQ(floor["source"], pairs);
  EXPECT_GE(floor["groups"].get<int>(), 2);
  EXPECT_EQ(floor["histories"].get<int>(), 2 * floor["groups"].get<int>());  // position pairs
  for (const char* c : {"normal", "tangential", "moment"}) {
    ASSERT_TRUE(floor["rms"][c].is_number()) << c;
    // Replicates of one state lie closer together than the paper's law lies from them.
    EXPECT_GT(floor["rms"][c].get<double>(), 0.0) << c;
    EXPECT_LT(floor["rms"][c].get<double>(),
              doc["force_history"][0]["heldout_rms"][c].get<double>())
        << c;
  }
  const RunResult own = ricochet("ladder " + quote(resolved) + " --add crater_rim --json");
  ASSERT_EQ(own.status, 0) << own.err;
  EXPECT_FALSE(nlohmann::json::parse(own.out).contains("force_history_floor"));
}

// A held law predicts the contact features with its own stiffness: on a set with penetration
// and durations, `--hold kn` keeps kn out of the fit (which would otherwise calibrate it from
// the features), and a model file with nothing calibrated and kn held is evaluated as given,
// its features compared, nothing refitted; its predictions then do not depend on the data's
// outputs, so a second kn gives other feature errors.
TEST_F(CmdDiagnosis, AHeldLawPredictsTheContactFeaturesWithoutRefitting) {
  const std::string resolved =
      std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/sand-verification-1.5e9.h5";
  const RunResult fitted = ricochet("compare " + quote(resolved) + " --hold kn --json");
  ASSERT_EQ(fitted.status, 0) << fitted.err;
  EXPECT_EQ(nlohmann::json::parse(fitted.out)["calibrated"],
            (std::vector<std::string>{"en2", "mu", "muR"}));
  const std::string law = (dir_ / "held.toml").string();
  std::ofstream(law) << "effects = [\"normal\", \"tangential\", \"rolling\"]\n"
                        "calibrate = []\nhold = [\"kn\"]\n[parameters]\nen2 = 0.05\n";
  std::vector<double> duration;
  for (const char* kn : {"3e6", "1e7"}) {
    const RunResult r = ricochet("compare " + quote(resolved) + " --model " + quote(law) +
                                 " --set kn=" + kn + " --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto doc = nlohmann::json::parse(r.out);
    EXPECT_TRUE(doc["calibrated"].empty()) << doc["calibrated"];
    EXPECT_EQ(doc["parameters"]["kn"].get<double>(), std::stod(kn));
    duration.push_back(doc["heldout_per_component"]["contact_duration"].get<double>());
  }
  // A stiffer held kn shortens the law's contacts, which are already far shorter than the
  // resolved ones (90 ms): the duration error grows.
  EXPECT_GT(duration[1], duration[0]);
  const RunResult bad = ricochet("compare " + quote(resolved) + " --hold k_n");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--hold"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("kn"), std::string::npos) << bad.err;
}

// --floor-replicates: the stiff bed's verification (one bed position per lab state, no
// replicates) borrows the position-pair scatter of the calibration campaign on the same grains'
// stiffness; its floor's standard deviations are then that campaign's own replicate floor's, and
// a file without replicates is refused naming the option and the file.
TEST_F(CmdDiagnosis, ASetWithoutReplicatesBorrowsTheFloorOfACampaignWithThem) {
  const std::string resolved = std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/";
  const std::string verification = resolved + "sand-verification-1.5e9.h5";
  const std::string calibration = resolved + "sand-calibration-1.5e9.h5";
  const RunResult own = ricochet("compare " + quote(calibration) + " --no-release-fits --json");
  ASSERT_EQ(own.status, 0) << own.err;
  const auto own_floor = nlohmann::json::parse(own.out)["noise_floor"];
  ASSERT_EQ(own_floor["source"], "replicates");
  const RunResult borrowed =
      ricochet("compare " + quote(verification) + " --no-release-fits --floor-replicates " +
               quote(calibration) + " --json");
  ASSERT_EQ(borrowed.status, 0) << borrowed.err;
  const auto floor = nlohmann::json::parse(borrowed.out)["noise_floor"];
  EXPECT_EQ(floor["source"], "borrowed replicates");
  for (const char* k : {"vx", "vy", "w", "penetration", "contact_duration"})
    EXPECT_NEAR(floor["sigma"][k].get<double>(), own_floor["sigma"][k].get<double>(),
                1e-9 * own_floor["sigma"][k].get<double>())
        << k;
  const RunResult bad = ricochet("compare " + quote(verification) + " --floor-replicates " +
                                 quote(kLab + "cylinders.csv"));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--floor-replicates"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("cylinders.csv"), std::string::npos) << bad.err;
}

// --floor-where: only some of the borrowed file's releases lend their scatter. The blind
// triangles borrow the bed-to-bed scatter of the stiffness plateau's 1.5e9 Pa triangle states
// (6 states x 3 beds; the file also holds 1.5e7 and 1.5e8 Pa, whose softer beds scatter
// otherwise): the floor's V_out^x sigma is the pooled within-state sd of those 18 releases,
// computed here by hand from the file; a filter that keeps nothing is refused naming the option.
TEST_F(CmdDiagnosis, TheBorrowedFloorCanBeOneLevelOfACampaign) {
  const std::string resolved = std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/";
  const std::string blind = quote(resolved + "sand-blind-triangles-1.5e9.h5");
  const std::string plateau = resolved + "stiffness-plateau.h5";
  const std::string level = "id^=E1.5e9-T";
  const RunResult r =
      ricochet("compare " + blind + " --where \"id^=T\" --no-release-fits" +
               " --floor-replicates " + quote(plateau) + " --floor-where \"" + level + "\" --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto floor = nlohmann::json::parse(r.out)["noise_floor"];
  EXPECT_EQ(floor["source"], "borrowed replicates");
  EXPECT_NE(floor["description"].get<std::string>().find(level), std::string::npos);
  // By hand: group the 1.5e9 Pa triangle releases by their id less the bed's "-sN".
  std::map<std::string, std::vector<double>> groups;
  for (const Impact& im : read_impact_set(plateau).impacts)
    if (im.id.starts_with("E1.5e9-T"))
      groups[im.id.substr(0, im.id.rfind("-s"))].push_back(im.vout[kVx]);
  ASSERT_EQ(groups.size(), 6u);
  double ss = 0;
  std::size_t dof = 0;
  for (const auto& [state, v] : groups) {
    double mean = 0;
    for (double x : v) mean += x / static_cast<double>(v.size());
    for (double x : v) ss += (x - mean) * (x - mean);
    dof += v.size() - 1;
  }
  EXPECT_NEAR(floor["sigma"]["vx"].get<double>(), std::sqrt(ss / static_cast<double>(dof)), 1e-9);
  // All levels pooled give another floor: the filter is what chose the releases.
  const RunResult all = ricochet("compare " + blind + " --where \"id^=T\" --no-release-fits" +
                                 " --floor-replicates " + quote(plateau) + " --json");
  ASSERT_EQ(all.status, 0) << all.err;
  EXPECT_GT(std::abs(nlohmann::json::parse(all.out)["noise_floor"]["sigma"]["vx"].get<double>() -
                     floor["sigma"]["vx"].get<double>()),
            1e-4);
  const RunResult none = ricochet("compare " + blind + " --floor-replicates " + quote(plateau) +
                                  " --floor-where \"id^=E9\"");
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.err.find("--floor-where"), std::string::npos) << none.err;
  EXPECT_NE(none.err.find("stiffness-plateau.h5"), std::string::npos) << none.err;
  // The report's per-file filter needs a file to filter: refused before any work, naming it.
  const std::string out = " --out " + quote((dir_ / "floor-where.html").string());
  for (const std::string& floors : {std::string(), std::string(" --data-floor-replicates \"\"")}) {
    const RunResult r =
        ricochet("report " + blind + floors + " --data-floor-where \"" + level + "\"" + out);
    EXPECT_EQ(r.status, 2) << floors;
    EXPECT_NE(r.err.find("--data-floor-where"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "floor-where.html"));
}

TEST_F(CmdDiagnosis, AUserPluginEffectTakesPartLikeTheBuiltIns) {
  // The tutorial's plugin (examples/user-effect): hidden in the truth, found by the diagnosis
  // among the built-ins, and climbed by the ladder.
  const std::string plugin = quote(RICOCHET_PLUGIN);
  const std::string data = (dir_ / "g.csv").string();
  const RunResult s = ricochet("synth --plugin " + plugin +
                               " --n 40 --seed 3 --design wide --set en2=0.2 --set mu=0.4 "
                               "--set muR=0.15 --add grazing_restitution --set kg=1.5 --out " +
                               quote(data));
  ASSERT_EQ(s.status, 0) << s.err;
  const RunResult d =
      ricochet("diagnose " + quote(data) + " --plugin " + plugin + " --no-release-fits --json");
  ASSERT_EQ(d.status, 0) << d.err;
  const auto doc = nlohmann::json::parse(d.out);
  // The family: the five catalog effects, the plugin and the 40 generated laws, calibrated
  // (ranking) or only score-tested (screened_out). (At n = 20 the plugin's score test gave
  // T = 3.2, adjusted p = 0.10 against the 46; at n = 40, T = 4.8, adjusted p = 0.001.)
  ASSERT_GE(doc["ranking"].size(), 1u);
  EXPECT_EQ(doc["family_size"].get<std::size_t>(), 46u);
  EXPECT_EQ(doc["family_size"].get<std::size_t>(),
            doc["ranking"].size() + doc["screened_out"].size());
  EXPECT_EQ(doc["ranking"][0]["effect"], "grazing_restitution") << doc["ranking"].dump(1);
  EXPECT_TRUE(doc["ranking"][0]["supported"].get<bool>());
  EXPECT_FALSE(doc["ranking"][0]["evidence"].get<std::string>().empty());

  const RunResult l = ricochet("ladder " + quote(data) + " --plugin " + plugin +
                               " --add grazing_restitution --json");
  ASSERT_EQ(l.status, 0) << l.err;
  const auto lad = nlohmann::json::parse(l.out);
  ASSERT_EQ(lad["rungs"].size(), 2u);
  EXPECT_LT(lad["rungs"][1]["heldout_error"].get<double>(),
            lad["rungs"][0]["heldout_error"].get<double>());
  EXPECT_TRUE(lad["rungs"][1]["parameters"].contains("kg"));
}

TEST_F(CmdDiagnosis, ErrorsNameTheOption) {
  const std::string cyl = quote(kLab + "cylinders.csv");
  struct Bad {
    std::string args, field;
  };
  for (const Bad& b : std::vector<Bad>{
           {"diagnose " + cyl + " --folds 1", "--folds"},
           {"diagnose " + cyl + " --folds x", "--folds"},
           {"diagnose " + cyl + " --error relative", "--error"},
           {"ladder " + cyl + " --add no_such_effect", "--add"},
           {"ladder " + cyl, "--add"},
           {"compare " + cyl + " --shape triangle", "shape"},
           {"synth --n 3 --noise loud --out " + quote((dir_ / "x.csv").string()), "--noise"},
           {"synth --n 3 --scatter en2 --out " + quote((dir_ / "x.csv").string()), "--scatter"},
           {"synth --n 3 --out " + quote((dir_ / "x.txt").string()), "--out"},
           {"report " + cyl + " --out " + quote((dir_ / "r.pdf").string()), "--out"},
       }) {
    const RunResult r = ricochet(b.args);
    EXPECT_EQ(r.status, 2) << b.args << "\n" << r.err;
    EXPECT_NE(r.err.find("'" + b.field + "'"), std::string::npos) << b.args << "\n" << r.err;
  }
}

// `report --against LAB`: a set of LAB's shape is compared with it (means, KS, the lab's gross
// errors, the exit slip of a disc); LAB itself, given as DATA too, is not compared with itself.
TEST_F(CmdDiagnosis, ReportComparesEachSetWithTheLabOfItsShape) {
  const std::string data = make_set("a");
  const std::string lab = kLab + "cylinders.csv";
  const fs::path html = dir_ / "against.html";
  const RunResult r =
      ricochet("report " + quote(data) + " " + quote(lab) + " --against " + quote(lab) +
               " --against " + quote(kLab + "triangles.csv") +
               " --rounds 0 --folds 3 --no-intervals --json --out " + quote(html.string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["sets"].size(), 2u);
  const auto& synth = doc["sets"][0];
  ASSERT_TRUE(synth.contains("against_lab")) << synth.dump();
  const auto& a = synth["against_lab"];
  EXPECT_EQ(a["data"], lab);
  for (const char* c : {"vout_x", "vout_y", "wout", "slip_out"})
    EXPECT_TRUE(a["components"].contains(c)) << c;
  // The six releases the gross-error rule flags on the lab alone (tests/stats/robust_test.cpp).
  std::vector<std::string> ids;
  for (const auto& g : a["checks"]["lab_gross_errors"]) ids.push_back(g["id"]);
  EXPECT_EQ(ids, (std::vector<std::string>{"C07", "C08", "C12", "C13", "C15", "C24"}));
  // The lab's own statistics, as stats reports them (paper Table 2: 3.06 +- 0.28 m/s).
  EXPECT_NEAR(a["components"]["vout_x"]["lab_mean"].get<double>(), 3.055, 0.001);
  EXPECT_EQ(a["components"]["vout_x"]["lab_core"]["n"], 22);
  EXPECT_EQ(a["sentence"].get<std::string>().find("Against the lab ("), 0u);
  EXPECT_FALSE(doc["sets"][1].contains("against_lab")) << "the lab compared with itself";
  const std::string page = slurp(html);
  EXPECT_NE(page.find("<details><summary>Against the lab in numbers"), std::string::npos);
  EXPECT_NE(page.find(a["sentence"].get<std::string>().substr(0, 40)), std::string::npos);
}

// A set run at lab releases (its ids name them: "C01-s0" was run at C01) is compared with those
// releases only, like with like; --data-where gives the same file twice as two halves, each
// compared with its own half of the lab. Ten of the lab's cylinders, V_out^x raised by 0.3 m/s.
TEST_F(CmdDiagnosis, ReportComparesACampaignRunAtLabReleasesWithThoseReleases) {
  std::ifstream in(kLab + "cylinders.csv");
  std::ofstream out(dir_ / "run-at-lab.csv");
  std::vector<double> lab_vx;
  int rows = 0;
  for (std::string line; std::getline(in, line) && rows < 10;) {
    if (line.empty() || line[0] == '#' || line.rfind("id,", 0) == 0) {
      out << line << "\n";
      continue;
    }
    std::vector<std::string> cell;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cell.push_back(c);
    lab_vx.push_back(std::stod(cell[5]));
    cell[0] += "-s0";
    cell[5] = std::to_string(std::stod(cell[5]) + 0.3);
    for (std::size_t k = 0; k < cell.size(); ++k) out << (k ? "," : "") << cell[k];
    out << "\n";
    ++rows;
  }
  out.close();
  const std::string data = quote((dir_ / "run-at-lab.csv").string());
  const RunResult r = ricochet("report " + data + " " + data + " --data-where \"vin_x<2.9\" " +
                               "--data-where \"\" --against " + quote(kLab + "cylinders.csv") +
                               " --rounds 0 --folds 3 --no-intervals --json " + "--out " +
                               quote((dir_ / "matched.html").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["sets"].size(), 2u);
  const auto& whole = doc["sets"][1]["against_lab"];
  EXPECT_TRUE(whole["matched_releases"].get<bool>());
  EXPECT_EQ(whole["releases"], 10);
  double mean = 0;
  for (double v : lab_vx) mean += v / static_cast<double>(lab_vx.size());
  EXPECT_NEAR(whole["components"]["vout_x"]["lab_mean"].get<double>(), mean, 1e-9);
  EXPECT_NEAR(whole["components"]["vout_x"]["difference"].get<double>(), 0.3, 1e-6);
  EXPECT_NE(whole["sentence"].get<std::string>().find("10 releases: those this set was run at"),
            std::string::npos)
      << whole["sentence"];
  const auto& half = doc["sets"][0]["against_lab"];
  EXPECT_LT(half["releases"].get<int>(), 10);
  EXPECT_GT(half["releases"].get<int>(), 0);
  EXPECT_NEAR(half["components"]["vout_x"]["difference"].get<double>(), 0.3, 1e-6);
  // A filter per DATA file or none: a count that does not match is refused.
  const RunResult bad = ricochet("report " + data + " " + data + " --data-where \"vin_x<2.9\" " +
                                 "--out " + quote((dir_ / "bad.html").string()));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("'--data-where'"), std::string::npos) << bad.err;
}

// --data-floor-replicates: per DATA file, the report's own --floor-replicates. The stiff bed's
// verification given twice, once borrowing the calibration campaign's position pairs: that
// section's floor is compare's borrowed one, the other keeps its declared floor; a count that
// does not match the DATA files is refused naming the option.
TEST_F(CmdDiagnosis, ReportBorrowsAFloorPerDataFile) {
  const std::string resolved = std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/";
  const std::string verification = quote(resolved + "sand-verification-1.5e9.h5");
  const std::string calibration = quote(resolved + "sand-calibration-1.5e9.h5");
  const RunResult c = ricochet("compare " + verification +
                               " --no-release-fits --floor-replicates " + calibration + " --json");
  ASSERT_EQ(c.status, 0) << c.err;
  const double borrowed = nlohmann::json::parse(c.out)["noise_floor"]["value"].get<double>();
  const RunResult r = ricochet("report " + verification + " " + verification +
                               " --data-floor-replicates " + calibration +
                               " --data-floor-replicates \"\" --rounds 0 --folds 3 "
                               "--no-intervals --json --out " +
                               quote((dir_ / "borrowed.html").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto sets = nlohmann::json::parse(r.out)["sets"];
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(sets[0]["noise_floor_source"], "borrowed replicates");
  EXPECT_NEAR(sets[0]["noise_floor"].get<double>(), borrowed, 1e-9 * borrowed);
  EXPECT_NE(sets[1]["noise_floor_source"], "borrowed replicates");
  EXPECT_LT(sets[1]["noise_floor"].get<double>(), borrowed);
  // The force histories of each rung, and their replicate floor from the same borrowed file
  // (the verification has no replicates of its own: the second section has none).
  for (const auto& set : sets) ASSERT_EQ(set["force_history"].size(), set["ladder"].size());
  ASSERT_TRUE(sets[0].contains("force_history_floor"));
  EXPECT_EQ(sets[0]["force_history_floor"]["source"], resolved + "sand-calibration-1.5e9.h5");
  EXPECT_FALSE(sets[1].contains("force_history_floor"));
  // The file given twice shows its first impact's picture once; the second section points to it.
  // (Each figure's caption is on the page as often as the page repeats a caption: counted against
  // the ladder figure, which each section has.)
  const std::string page = test::slurp(dir_ / "borrowed.html");
  const auto count = [&](const std::string& text) {
    std::size_t n = 0;
    for (auto at = page.find(text); at != std::string::npos; at = page.find(text, at + 1)) ++n;
    return n;
  };
  const std::size_t pictures = count("One impact of this campaign (LIGGGHTS), side view");
  const std::size_t ladders = count("Each rung adds one effect and is recalibrated");
  ASSERT_GT(pictures, 0u);
  EXPECT_EQ(2 * pictures, ladders);
  EXPECT_NE(page.find("first impact, through the contact, is pictured in the section"),
            std::string::npos);
  EXPECT_EQ(count("in brackets over the replicate floor"), 1u);
  const RunResult bad =
      ricochet("report " + verification + " " + verification + " --data-floor-replicates " +
               calibration + " --out " + quote((dir_ / "bad.html").string()));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--data-floor-replicates"), std::string::npos) << bad.err;
}

// A set whose declared uncertainties are tiny (a LIGGGHTS campaign: the reconstruction's
// standard errors) misses its floor by thousands: the headline gives that ratio without
// meaningless decimals and the numbers behind it, with the model-free yardstick (how much
// releases with similar incident states differ). A lab set near its floor keeps two decimals.
TEST_F(CmdDiagnosis, ReportHeadlineGivesTheNumbersBehindAHugeRatio) {
  const std::string resolved =
      std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/lab-triangles-blind-rolling-gb.h5";
  const RunResult r = ricochet("report " + quote(resolved) + " " + quote(kLab + "cylinders.csv") +
                               " --rounds 0 --folds 3 --orientations 2 --no-intervals --json "
                               "--out " +
                               quote((dir_ / "huge.html").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["sets"].size(), 2u);
  const std::string huge = doc["sets"][0]["headline"];
  const std::string lab = doc["sets"][1]["headline"];
  EXPECT_TRUE(std::regex_search(huge, std::regex("misses the data by [0-9]{3,} x the noise floor "
                                                 "\\(held-out error [0-9.]+ against a floor of")))
      << huge;
  EXPECT_NE(huge.find("from the set's declared uncertainties; releases with similar incident "
                      "states differ by"),
            std::string::npos)
      << huge;
  EXPECT_FALSE(std::regex_search(huge, std::regex("[0-9]{3,}\\.[0-9]+ x"))) << huge;
  EXPECT_TRUE(std::regex_search(lab, std::regex("misses the data by [0-9]\\.[0-9]{2} x the noise "
                                                "floor, worst on")))
      << lab;
  EXPECT_EQ(lab.find("held-out error"), std::string::npos) << lab;
}

// A resolved campaign that keeps its tracks shows one impact's contact in time beside the reduced
// law (issue 32, item 4; diagnosis/track_figure.hpp); a set without tracks shows none.
TEST_F(CmdDiagnosis, ReportShowsOneResolvedImpactInTime) {
  const std::string resolved = std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/lab-cylinders.h5";
  const fs::path html = dir_ / "tracks.html";
  const RunResult r = ricochet("report " + quote(resolved) + " " + quote(kLab + "cylinders.csv") +
                               " --where 'vin_x<2.8' --rounds 0 --folds 3 --no-intervals --out " +
                               quote(html.string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string page = slurp(html);
  const auto second = page.find("<h2 id=\"set2\">");
  ASSERT_NE(second, std::string::npos);
  const std::string alt = "alt=\"One impact of this campaign in time";
  const auto figure = page.find(alt);
  ASSERT_NE(figure, std::string::npos) << "no contact figure";
  EXPECT_LT(figure, second) << "the figure is not in the campaign's section";
  EXPECT_EQ(page.find(alt, figure + 1), std::string::npos) << "more than one";
  EXPECT_NE(page.find("LIGGGHTS forces are scaled to the lab block", figure), std::string::npos);
}

// `diagnose` on a campaign file that keeps its tracks reports the force the base law leaves along
// each release's own path (issue 33, item 2; diagnosis/force_residual.hpp): every release with a
// track, the slab's forces scaled to the lab block by m_lab / m_slab (13.9 kg over the 0.06 m
// slab's 2.876 kg: 4.83), the shape's overlap on the path within a grain radius (3 mm) of the
// track's own penetration, a normal law whose held-out residual is below the residual (it
// explains part of it), each selected term with its unit and interval, and its time. A CSV set has
// no histories: no force_law key.
TEST_F(CmdDiagnosis, DiagnoseReportsTheForceLawOfACampaignsHistories) {
  const std::string resolved = std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/lab-cylinders.h5";
  const RunResult r = ricochet("diagnose " + quote(resolved) +
                               " --folds 3 --repeats 1 --no-release-fits --no-pairs --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_TRUE(doc.contains("force_law")) << r.out.substr(0, 2000);
  const auto& fl = doc["force_law"];
  EXPECT_EQ(fl["ids"].size(), doc["releases"].get<std::size_t>());
  EXPECT_NEAR(fl["force_scale"][0].get<double>(), 13.9 / 2.876, 0.01);
  EXPECT_LT(fl["geometry_mismatch_m"].get<double>(), 3e-3);
  EXPECT_EQ(fl["base"], "population fit");
  EXPECT_GT(fl["seconds"].get<double>(), 0.0);  // its own wall time (bench.sh's force section)
  bool normal = false;
  for (const auto& law : fl["laws"]) {
    if (law["component"] != "normal") continue;
    normal = true;
    EXPECT_LT(law["heldout_rms"].get<double>(), law["rms_residual"].get<double>());
    ASSERT_FALSE(law["terms"].empty());
    for (const auto& t : law["terms"]) {
      EXPECT_FALSE(t["unit"].get<std::string>().empty());
      EXPECT_LE(t["lo"].get<double>(), t["coefficient"].get<double>());
      EXPECT_GE(t["hi"].get<double>(), t["coefficient"].get<double>());
    }
  }
  EXPECT_TRUE(normal);
  const RunResult text = ricochet("diagnose " + quote(resolved) +
                                  " --folds 3 --repeats 1 --no-release-fits --no-pairs");
  ASSERT_EQ(text.status, 0) << text.err;
  // --no-release-fits: the residual is taken at the population fit, and says so.
  EXPECT_NE(text.out.find("force law missing from the model (population fit), from the contact "
                          "histories of"),
            std::string::npos);
  const RunResult csv = ricochet("diagnose " + quote(kLab + "cylinders.csv") +
                                 " --folds 3 --repeats 1 --no-release-fits --no-pairs --json");
  ASSERT_EQ(csv.status, 0) << csv.err;
  EXPECT_FALSE(nlohmann::json::parse(csv.out).contains("force_law"));
}

TEST_F(CmdDiagnosis, ReportRendersInHeadlessChromiumWithEveryFigureShown) {
  if (chromium_missing())
    GTEST_SKIP() << "no /usr/bin/chromium: the report is not rendered (apt install chromium)";
  const std::string data = make_set("r");
  const fs::path html = dir_ / "report.html";
  const RunResult r = ricochet("report " + quote(data) +
                               " --label synthetic --rounds 1 "
                               "--folds 3 --no-intervals --json --out " +
                               quote(html.string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  const int figures = doc["figures"].get<int>();
  EXPECT_GE(figures, 10);
  ASSERT_EQ(doc["sets"].size(), 1u);
  EXPECT_FALSE(doc["sets"][0]["conclusion"].get<std::string>().empty());

  const std::string page = slurp(html);
  for (const char* section : {"Conclusions", "Model", "Method"})
    EXPECT_NE(page.find(std::string(">") + section + "</h"), std::string::npos) << section;
  // Each set opens with its one-sentence headline; the numbers are in collapsible blocks.
  const std::string headline = doc["sets"][0]["headline"];
  EXPECT_NE(page.find("<p class=\"verdict\">"), std::string::npos);
  EXPECT_EQ(headline.find("The model "), 0u) << headline;
  EXPECT_NE(headline.find("x the noise floor"), std::string::npos) << headline;
  for (const char* block :
       {"Conclusion in numbers", "Data", "Comparison", "Diagnosis", "Model ladder in numbers"})
    EXPECT_NE(page.find(std::string("<details><summary>") + block), std::string::npos) << block;

  const RenderedFigures shown = render_in_chromium(html, dir_);
  ASSERT_GE(shown.total, 0) << "the probe did not run in Chromium";
  EXPECT_EQ(shown.total, figures);
  EXPECT_EQ(shown.shown, figures) << "some figures did not render";
  // Every figure has drawn content: more than 1 % of its pixels are not background (an empty
  // gnuplot frame with axes and titles alone is about 2-4 %; a plotted figure 5-30 %).
  ASSERT_EQ(shown.ink.size(), static_cast<std::size_t>(figures));
  for (std::size_t k = 0; k < shown.ink.size(); ++k)
    EXPECT_GT(shown.ink[k], 0.01) << "figure " << k + 1 << " is blank";
  // No legend lies inside a plot area, where it could cover a point.
  EXPECT_GT(shown.legend_entries, 0) << "no legend found: the check would be vacuous";
  EXPECT_TRUE(shown.overlapping.empty()) << shown.overlapping.front();
  // A screenshot of the page's top for people (kept under the build folder, a CI artefact).
  const fs::path png = screenshot(html, dir_, "report-top.png");
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 20000u) << "the screenshot is (nearly) blank";
}

}  // namespace
}  // namespace ricochet
