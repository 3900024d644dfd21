// The options declared once for every subcommand (cli/shared_options.hpp): --vin parsed by one
// function with one message on every command that takes it, and --where accepted by every command
// that reads an impact set, applied before any work (a filter keeping nothing exits 2 at once) and
// filtering (fewer releases with it than without).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/program_test.hpp"

namespace ricochet {
namespace {

using test::quote;

const std::string kCyl = quote(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
const std::string kCampaignPlateau =
    quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/stiffness-plateau.h5");
const std::string kCampaign =
    quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/convergence.h5");

class SharedOptions : public test::ProgramTest {
 protected:
  // The command's --json document; an empty object (and a failure) when it does not succeed.
  nlohmann::json json(const std::string& args) {
    const test::RunResult r = ricochet(args + " --json");
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return r.status == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
  }
};

// Every --vin: one parser, one message, exit status 2, nothing on stdout.
TEST_F(SharedOptions, VinHasOneParserAndOneMessage) {
  const std::vector<std::string> commands = {"simulate", "transfer predict --seed 1 --from " + kCyl,
                                             "montecarlo --n 10", "sobol --n 16", "dem impact"};
  for (const std::string& command : commands) {
    if (test::needs_liggghts(command) && !test::program_has_liggghts()) continue;
    for (const std::string vin : {"1,2", "1,-2,3,4", "1,x,3", "1,,3", "1,-2,nan"}) {
      const test::RunResult r = ricochet(command + " --vin " + vin);
      EXPECT_EQ(r.status, 2) << command << " --vin " << vin << "\n" << r.err;
      EXPECT_NE(
          r.err.find("field '--vin': expected 3 numbers vx,vy,omega [m/s, m/s, rad/s], got '" +
                     vin + "'"),
          std::string::npos)
          << command << " --vin " << vin << "\n"
          << r.err;
      EXPECT_TRUE(r.out.empty()) << command;
    }
  }
  // A block moving up is refused wherever the state is a collision's.
  for (const std::string command :
       {"simulate", "montecarlo --n 10", "sobol --n 16", "dem impact"}) {
    if (test::needs_liggghts(command) && !test::program_has_liggghts()) continue;
    const test::RunResult r = ricochet(command + " --vin 2.9,2.3,-65");
    EXPECT_EQ(r.status, 2) << command << "\n" << r.err;
    EXPECT_NE(r.err.find("incident vy must be negative (downwards), got '2.9,2.3,-65'"),
              std::string::npos)
        << command << "\n"
        << r.err;
  }
  // Negative first components and blanks parse.
  const test::RunResult ok = ricochet("simulate --vin ' -2.9, -2.3 ,-65' --json");
  ASSERT_EQ(ok.status, 0) << ok.err;
  EXPECT_EQ(nlohmann::json::parse(ok.out)["model"].is_object(), true);
}

// Every command that reads an impact set takes --where and applies it before any work: a filter
// that keeps no release is bad input (status 2) naming --where, at once.
TEST_F(SharedOptions, WhereOnEveryCommandThatReadsAnImpactSet) {
  const std::string none = " --where \"vin_x>100\"";
  const std::string out = quote((dir_ / "out.html").string());
  const std::vector<std::string> commands = {
      "stats " + kCyl,
      "paired " + kCampaignPlateau + " --base E1.5e7- --against E1.5e8-",
      "transfer fit " + kCyl,
      "transfer predict --seed 1 --vin 2.9,-2.3,-65 --from " + kCyl,
      "calibrate " + kCyl,
      "montecarlo --n 10 --compare " + kCyl,
      "montecarlo --n 10 --incident " + kCyl,
      "synth --incident " + kCyl + " --out " + quote((dir_ / "s.csv").string()),
      "compare " + kCyl,
      "diagnose " + kCyl,
      "ladder " + kCyl + " --add rate_restitution",
      "report " + kCyl + " --out " + out,
      "upscale " + kCampaign,
      "calibrate-grains " + kCampaign + " --lab " + kCyl};
  for (const std::string& command : commands) {
    if (test::needs_liggghts(command) && !test::program_has_liggghts()) continue;
    const test::RunResult r = ricochet(command + none);
    EXPECT_EQ(r.status, 2) << command << "\n" << r.err;
    EXPECT_NE(r.err.find("--where"), std::string::npos) << command << "\n" << r.err;
    EXPECT_NE(r.err.find("vin_x>100"), std::string::npos) << command << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << command << "\n" << r.out;
  }
}

// And it filters: fewer releases with it than without, the same count everywhere.
TEST_F(SharedOptions, WhereFilters) {
  const std::string where = " --where \"vin_x<3\"";
  const std::size_t all = json("stats " + kCyl)["n"].get<std::size_t>();
  const std::size_t some = json("stats " + kCyl + where)["n"].get<std::size_t>();
  ASSERT_EQ(all, 28u);
  ASSERT_GT(some, 0u);
  ASSERT_LT(some, all);
  EXPECT_EQ(json("transfer fit " + kCyl + where)["n"], some);
  EXPECT_EQ(
      json("transfer predict --seed 1 --from " + kCyl + " --incident " + kCyl + where)["incidents"],
      some);
  EXPECT_EQ(json("montecarlo --n 200 --compare " + kCyl + where)["compare"]["releases"], some);
  EXPECT_EQ(json("montecarlo --n 200 --compare " + kCyl)["compare"]["releases"], all);
}

// `paired` pools several files (a side study beside its campaign): the floor check's stiff-wall
// impacts pair with the plateau campaign's soft-wall ones, one pair per stiff-wall impact, and a
// file given twice is refused (its ids would pair ambiguously).
TEST_F(SharedOptions, PairedPoolsFiles) {
  const std::string wall =
      quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/wall-stiffness.h5");
  const test::RunResult n = ricochet("stats " + wall + " --json");
  ASSERT_EQ(n.status, 0) << n.err;
  const test::RunResult r = ricochet("paired " + kCampaignPlateau + " " + wall +
                                     " --base E1.5e9-cyl- --against E1.5e9-wall1.5e9-cyl- --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["pairs"].size(), nlohmann::json::parse(n.out)["n"].get<std::size_t>());
  const test::RunResult twice = ricochet("paired " + kCampaignPlateau + " " + kCampaignPlateau +
                                         " --base E1.5e7- --against E1.5e8-");
  EXPECT_EQ(twice.status, 2);
  EXPECT_NE(twice.err.find("pooled files need distinct ids"), std::string::npos) << twice.err;
}

// calibrate-grains' --lab-where filters the target, not the campaign: its target mean and sd are
// those `stats --where` gives for the same filter (a half of scripts/lab-split.py's kind), and
// they differ from the whole set's.
TEST_F(SharedOptions, LabWhereSelectsTheTarget) {
  const std::string grains =
      "calibrate-grains " +
      quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/bed-calibration-cdt.h5") +
      " --lab " + kCyl;
  if (!test::program_has_liggghts()) GTEST_SKIP() << "calibrate-grains needs LIGGGHTS";
  const std::string where = "id!=C02 && id!=C04 && id!=C07 && id!=C08 && vin_x<3.2";
  const auto half = json(grains + " --lab-where \"" + where + "\"");
  const auto all = json(grains);
  const auto stats = json("stats " + kCyl + " --where \"" + where + "\"");
  ASSERT_TRUE(half.contains("components") && all.contains("components") &&
              stats.contains("columns"));
  EXPECT_EQ(half["target_where"], where);
  EXPECT_EQ(half["target_impacts"], stats["n"]);
  EXPECT_LT(half["target_impacts"].get<int>(), all["target_impacts"].get<int>());
  for (const char* c : {"vout_x", "vout_y", "wout"}) {
    EXPECT_NEAR(half["components"][c]["target_mean"].get<double>(),
                stats["columns"][c]["mean"].get<double>(), 1e-12)
        << c;
    EXPECT_NEAR(half["components"][c]["target_sd"].get<double>(),
                stats["columns"][c]["std"].get<double>(), 1e-12)
        << c;
    EXPECT_NE(half["components"][c]["target_mean"], all["components"][c]["target_mean"]) << c;
  }
}

// upscale's --lab-where filters the lab it compares with (a held-out check compares a half with the
// same half), not the campaign: the lab's mean is `stats --where`'s, the campaign keeps its 28
// impacts, and the release-by-release pairs are the half's.
TEST_F(SharedOptions, UpscaleLabWhereSelectsTheLabHalf) {
  if (!test::program_has_liggghts()) GTEST_SKIP() << "upscale needs LIGGGHTS";
  const std::string upscale = "upscale " +
                              quote(std::string(RICOCHET_SOURCE_DIR) +
                                    "/data/resolved/lab-cylinders-default-calibrated-ground.h5") +
                              " --no-intervals --lab " + kCyl;
  const std::string where = "id!=C01 && id!=C03 && id!=C05 && id!=C06 && id!=C10";
  const auto half = json(upscale + " --lab-where \"" + where + "\"");
  const auto all = json(upscale);
  const auto stats = json("stats " + kCyl + " --where \"" + where + "\"");
  ASSERT_TRUE(half.contains("gap_to_lab") && all.contains("gap_to_lab"));
  EXPECT_EQ(half["lab_where"], where);
  EXPECT_EQ(half["impacts"].size(), all["impacts"].size());
  EXPECT_EQ(half["lab_checks"]["lab_residuals"]["n"], stats["n"]);
  EXPECT_EQ(all["lab_checks"]["lab_residuals"]["n"], 28);
  for (const char* c : {"vout_x", "vout_y", "wout"})
    EXPECT_NEAR(half["gap_to_lab"][c]["lab_mean"].get<double>(),
                stats["columns"][c]["mean"].get<double>(), 1e-12)
        << c;
}

// upscale --lab-same-ids compares a campaign run at lab states with the lab's releases of the same
// ids, after the campaign's --where: here the sand-only verification (27 rebounds; C08 was
// captured) less five, against the lab less the same five and C08, which is what --lab-where
// names by hand.
TEST_F(SharedOptions, UpscaleLabSameIdsIsTheLabOfTheCampaignsIds) {
  if (!test::program_has_liggghts()) GTEST_SKIP() << "upscale needs LIGGGHTS";
  const std::string upscale =
      "upscale " +
      quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/sand-verification-1.5e9.h5") +
      " --no-intervals --lab " + kCyl;
  const std::string where = "id!=C01 && id!=C03 && id!=C05 && id!=C06 && id!=C10";
  const auto same = json(upscale + " --where \"" + where + "\" --lab-same-ids");
  const auto by_hand =
      json(upscale + " --where \"" + where + "\" --lab-where \"" + where + " && id!=C08\"");
  EXPECT_EQ(same["lab_same_ids"], true);
  EXPECT_EQ(same["lab_checks"]["lab_residuals"]["n"], 22);
  EXPECT_EQ(by_hand["lab_checks"]["lab_residuals"]["n"], 22);
  for (const char* c : {"vout_x", "vout_y", "wout"})
    EXPECT_EQ(same["gap_to_lab"][c]["lab_mean"], by_hand["gap_to_lab"][c]["lab_mean"]) << c;
}

// upscale --write-model: the campaign's law (two groups here: the whole campaign's fit) held as a
// model file, which diagnose takes as a base it evaluates and does not refit.
TEST_F(SharedOptions, UpscaleWritesItsLawHeldAndDiagnoseKeepsIt) {
  if (!test::program_has_liggghts()) GTEST_SKIP() << "upscale needs LIGGGHTS";
  const std::string law = (dir_ / "bed-law.toml").string();
  const auto up =
      json("upscale " +
           quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/bed-probe-width-cdt.h5") +
           " --no-intervals --write-model " + quote(law));
  EXPECT_EQ(up["model_file"], law);
  ASSERT_GE(up["groups"].size(), 2u);
  const auto& fitted = up["campaign"]["params"];
  // Every parameter held: on a set with contact features (the campaign itself) kn is not
  // refitted either.
  const auto d = json("diagnose " + kCyl + " --model " + quote(law) + " --no-features");
  EXPECT_TRUE(d["base"]["calibrated"].empty());
  const auto c =
      json("compare " +
           quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/bed-probe-width-cdt.h5") +
           " --model " + quote(law) + " --no-release-fits");
  EXPECT_TRUE(c["calibrated"].empty()) << c["calibrated"];
  for (const char* p : {"en2", "mu", "muR"})
    EXPECT_DOUBLE_EQ(d["base"]["parameters"][p].get<double>(), fitted[p].get<double>()) << p;
  const test::RunResult bad =
      ricochet("upscale " +
               quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/bed-probe-width-cdt.h5") +
               " --write-model law.csv");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--write-model"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace ricochet
