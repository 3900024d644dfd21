// Issue 33, item 3: the loop closed on contact histories, through the `ricochet` program. The
// independent simulator (another integrator than the engine's; the engine's stiffnesses, so that
// the residual is the hidden force) makes 30 releases with a hidden Katsuragi-Durian drag
// (m/d1 = 40 kg/m, acting only while the block penetrates) and writes their tracked histories
// (independent_truth --tracks). Then:
//  - `diagnose --write-force-model` discovers the drag from the histories (the library's term acts
//    both ways, so its coefficient comes out a little under 40) and writes it as a model file;
//  - `ladder --force-law` adds it as a rung held at that coefficient, and the held-out error of
//    the force histories falls;
//  - `ladder --add term_inertial_drag` calibrates the same term on the rebounds alone, which do
//    not pin it.
// The seed is the first of scripts/force-loop.sh's five (docs/diagnosis.md has the five).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "support/program_test.hpp"

namespace ricochet {
namespace {

class ForceLoop : public test::ProgramTest {
 protected:
  // N releases of the hidden drag with their tracks, drawn with SEED.
  std::string make_set(int n = 30, int seed = 5101) {
    const std::string set = (dir_ / "set.h5").string();
    const std::string make =
        test::quote(RICOCHET_TRUTH_EXE) + " --family kd_drag --strength 1 --n " +
        std::to_string(n) + " --design wide --scatter narrow --engine-numerics --seed " +
        std::to_string(seed) + " --tracks --no-refit --out " + test::quote(set) + " > /dev/null";
    EXPECT_EQ(std::system(make.c_str()), 0);
    return set;
  }
};

TEST_F(ForceLoop, TheDiscoveredDragBecomesARungAndTheForceErrorFalls) {
  const std::string set = make_set();
  const std::string law = (dir_ / "law.toml").string();
  const test::RunResult d =
      ricochet("diagnose " + test::quote(set) + " --seed 5101 --write-force-model " +
               test::quote(law) + " --json");
  ASSERT_EQ(d.status, 0) << d.err;
  const auto dj = nlohmann::json::parse(d.out);
  ASSERT_TRUE(dj.contains("force_law"));
  EXPECT_EQ(dj["force_law"]["base"], "per-release fits");
  double drag = -1;
  for (const auto& l : dj["force_law"]["laws"])
    for (const auto& t : l["terms"])
      if (t["name"] == "inertial_drag") drag = t["coefficient"].get<double>();
  EXPECT_GT(drag, 30.0) << dj["force_law"].dump();
  EXPECT_LT(drag, 45.0) << dj["force_law"].dump();
  // The model file carries the term at that coefficient, not calibrated.
  std::ifstream in(law);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("term_inertial_drag"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("c_inertial_drag"), std::string::npos) << text.str();

  const test::RunResult l =
      ricochet("ladder " + test::quote(set) + " --seed 5101 --force-law --json");
  ASSERT_EQ(l.status, 0) << l.err;
  const auto lj = nlohmann::json::parse(l.out);
  ASSERT_EQ(lj["rungs"].size(), 2u);
  EXPECT_EQ(lj["rungs"][1]["added"], "term_inertial_drag");
  EXPECT_NEAR(lj["rungs"][1]["parameters"]["c_inertial_drag"].get<double>(), drag, 1e-9 * drag);
  // Held out leak-free: every split rediscovered the law on its training histories, and on
  // this set (a 40 kg/m drag, 30 releases) each found the drag again.
  const auto& split = lj["rungs"][1]["split_discovery"];
  ASSERT_TRUE(split.is_object()) << lj["rungs"][1].dump();
  EXPECT_GE(split["splits"].get<int>(), 5);
  EXPECT_GE(split["same_terms"].get<int>(), split["splits"].get<int>() - 1);
  ASSERT_EQ(lj["force_history"].size(), 2u);
  const double before = lj["force_history"][0]["heldout_rms"]["normal"].get<double>();
  const double after = lj["force_history"][1]["heldout_rms"]["normal"].get<double>();
  EXPECT_LT(after, 0.99 * before) << "held-out normal force RMS " << before << " -> " << after;
  EXPECT_TRUE(lj["force_history"][0]["heldout_rms"]["moment"].is_null());  // no torque tracked
}

// A named law (`--force-terms`): the drag alone, fitted on the histories without selection,
// comes out as the discovery's (30-45 kg/m against the truth's 40 acting one way), and every
// split fits the same term. An unknown name is refused before any work, naming the library, and
// so is a history weight without a floor to weigh the histories by.
TEST_F(ForceLoop, ANamedLawIsFittedOnTheHistoriesAsARung) {
  const std::string set = make_set();
  const test::RunResult bad =
      ricochet("ladder " + test::quote(set) + " --force-law --force-terms drag");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--force-terms"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("inertial_drag"), std::string::npos) << bad.err;
  // Histories but no replicates and no borrowed floor: nothing to weigh them by.
  const test::RunResult unweighed =
      ricochet("ladder " + test::quote(set) + " --add term_inertial_drag --history-weight 0.01");
  EXPECT_EQ(unweighed.status, 2);
  EXPECT_NE(unweighed.err.find("--history-weight"), std::string::npos) << unweighed.err;
  EXPECT_NE(unweighed.err.find("replicate floor"), std::string::npos) << unweighed.err;
  const test::RunResult l = ricochet("ladder " + test::quote(set) +
                                     " --seed 5101 --force-law --force-terms inertial_drag --json");
  ASSERT_EQ(l.status, 0) << l.err;
  const auto lj = nlohmann::json::parse(l.out);
  EXPECT_EQ(lj["force_law"]["named"], nlohmann::json::array({"inertial_drag"}));
  ASSERT_EQ(lj["rungs"].size(), 2u);
  EXPECT_EQ(lj["rungs"][1]["added"], "term_inertial_drag");
  const double drag = lj["rungs"][1]["parameters"]["c_inertial_drag"].get<double>();
  EXPECT_GT(drag, 30.0);
  EXPECT_LT(drag, 45.0);
  const auto& split = lj["rungs"][1]["split_discovery"];
  EXPECT_EQ(split["same_terms"], split["splits"]) << split.dump();
}

// `compare --history-weight`: the fits weigh the histories too (the option the three diagnosis
// commands share), so the calibrated model's in-sample force histories come nearer the measured
// ones than the rebound-only fit's, in the floors' units the objective uses, and the rebounds'
// in-sample error pays for it. The truth set has no replicates: the histories' floor is borrowed
// from the stiff bed's sand calibration (its 12 bed-position pairs keep their tracks), as the
// verification's ladder borrows it (docs/diagnosis.md). The paper's law cannot make the hidden
// drag, so the weight moves it only part of the way (about 0.84 of the squared floors here).
TEST_F(ForceLoop, CompareWeighsTheHistoriesWhenAsked) {
  const std::string set = make_set(16, 5102);
  // mean over components of (in-sample RMS / floor)^2: the objective's units
  const auto in_floors = [](const nlohmann::json& j) {
    double sum = 0;
    int n = 0;
    for (const char* c : {"normal", "tangential", "moment"}) {
      const auto& rms = j["force_history"]["insample_rms"][c];
      const auto& floor = j["force_history_floor"]["rms"][c];
      if (rms.is_null() || floor.is_null()) continue;
      sum += std::pow(rms.get<double>() / floor.get<double>(), 2);
      ++n;
    }
    return n > 0 ? sum / n : NAN;
  };
  const std::string args =
      " " + test::quote(set) + " --seed 5102 --no-release-fits --floor-replicates " +
      test::quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/sand-calibration-1.5e9.h5") +
      " --json";
  const std::string common = "compare" + args;
  const test::RunResult plain = ricochet(common);
  ASSERT_EQ(plain.status, 0) << plain.err;
  const auto pj = nlohmann::json::parse(plain.out);
  ASSERT_TRUE(pj.contains("force_history")) << "compare reports the histories of a set with them";
  ASSERT_TRUE(pj.contains("force_history_floor"));
  EXPECT_GE(pj["force_history_floor"]["groups"].get<int>(), 2);
  EXPECT_FALSE(pj.contains("history_weight"));
  const test::RunResult weighed = ricochet(common + " --history-weight 0.01");
  ASSERT_EQ(weighed.status, 0) << weighed.err;
  const auto wj = nlohmann::json::parse(weighed.out);
  EXPECT_EQ(wj["history_weight"].get<double>(), 0.01);
  const double before = in_floors(pj), after = in_floors(wj);
  ASSERT_TRUE(std::isfinite(before) && std::isfinite(after));
  EXPECT_LT(after, 0.9 * before) << "in-sample history error in floors^2: " << before << " -> "
                                 << after;
  EXPECT_GT(wj["insample_error"].get<double>(), pj["insample_error"].get<double>());
  // diagnose takes the same option into the same base fit (one option, one fit path)
  const test::RunResult d =
      ricochet("diagnose" + args + " --history-weight 0.01 --candidate inertial_drag");
  ASSERT_EQ(d.status, 0) << d.err;
  const auto dj = nlohmann::json::parse(d.out);
  EXPECT_EQ(dj["history_weight"].get<double>(), 0.01);
  EXPECT_DOUBLE_EQ(dj["base"]["insample_error"].get<double>(), wj["insample_error"].get<double>());
  EXPECT_DOUBLE_EQ(dj["base"]["parameters"]["mu"].get<double>(),
                   wj["parameters"]["mu"].get<double>());
}

// The report shows the residual force before and after the discovered law, and the law lowers
// it (in-sample: the terms were fitted to these residuals).
TEST_F(ForceLoop, TheReportShowsTheResidualForceFalling) {
  const std::string set = make_set();
  const std::string page = (dir_ / "r.html").string();
  const test::RunResult r = ricochet("report " + test::quote(set) + " --out " + test::quote(page));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(page);
  std::stringstream html;
  html << in.rdbuf();
  const std::regex rms("RMS ([0-9.]+) N before, ([0-9.]+) N after");
  std::smatch m;
  const std::string text = html.str();
  ASSERT_TRUE(std::regex_search(text, m, rms)) << "no force-residual figure";
  EXPECT_LT(std::stod(m[2]), 0.9 * std::stod(m[1])) << m[0];
  EXPECT_NE(text.find("Force law from the contact histories"), std::string::npos);
}

// Refused before any work: a set without histories.
TEST_F(ForceLoop, WithoutHistoriesTheForceOptionsAreRefusedAtOnce) {
  const std::string csv = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv";
  const test::RunResult d = ricochet("diagnose " + test::quote(csv) + " --write-force-model " +
                                     test::quote((dir_ / "m.toml").string()));
  EXPECT_EQ(d.status, 2);
  EXPECT_NE(d.err.find("--write-force-model"), std::string::npos) << d.err;
  const test::RunResult l = ricochet("ladder " + test::quote(csv) + " --force-law");
  EXPECT_EQ(l.status, 2);
  EXPECT_NE(l.err.find("--force-law"), std::string::npos) << l.err;
  for (const char* command : {"ladder", "compare", "diagnose"}) {
    const test::RunResult w = ricochet(std::string(command) + " " + test::quote(csv) +
                                       " --add inertial_drag --history-weight 0.03");
    EXPECT_EQ(w.status, 2) << command;
    EXPECT_NE(w.err.find("--history-weight"), std::string::npos) << command << ": " << w.err;
  }
}

}  // namespace
}  // namespace ricochet
