// Every subcommand driven with a bad option value: the exit status is 2 (bad input, the rule of
// docs/commands/README.md), the message names the option, nothing is written on stdout, and the
// run stops before any work (each case returns in well under a second).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <ostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/program_test.hpp"
#include "uq/montecarlo.hpp"

namespace ricochet {
namespace {

using test::quote;

const std::string kCyl = quote(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
const std::string kCampaign = quote(std::string(RICOCHET_SOURCE_DIR) +
                                    "/data/resolved/lab-cylinders-default-calibrated-ground.h5");

struct BadCase {
  std::string args;  // after `ricochet`
  std::string says;  // a substring of the message on stderr
};

void PrintTo(const BadCase& c, std::ostream* os) {
  *os << c.args;
}

// At least one case per subcommand (and per `dem` / `transfer` subcommand).
// A resolved campaign with two grain stiffnesses of the same impacts (ids E1.5e7-KEY, E1.5e8-KEY).
const std::string kPlateau =
    quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/stiffness-plateau.h5");

const std::vector<BadCase> kCases = {
    {"stats " + kCyl + " --bogus 1", "--bogus"},
    {"paired " + kPlateau + " --base E1.5e7- --against E1.5e8- --margin -1",
     "field '--margin': value -1 is outside [0, inf)"},
    {"paired " + kPlateau + " --base E1.5e7- --against E1.5e7-", "--against"},
    {"paired " + kPlateau + " --base X- --against Y-", "no pair of ids"},
    {"paired " + kPlateau + " --base E1.5e7- --against E1.5e8- --lab " + kCyl, "triangle"},
    {"reconstruct track.csv --k-sigma -1", "--k-sigma: value -1 is outside [0.001, 1000]"},
    {"reconstruct track.csv --pixel-size 0", "--pixel-size"},
    {"reconstruct track.csv --guard -2", "--guard"},
    {"transfer fit " + kCyl + " --replicates 0",
     "field '--replicates': value 0 is outside [1, 1e+07]"},
    {"transfer predict --seed 1 --from " + kCyl + " --vin 1,2", "--vin"},
    {"effects --plugin", "--plugin"},
    {"effects --out catalog.txt", "--out"},
    {"simulate --vin 2.9,-2.3,-65 --alpha 400", "--alpha: value 400 is outside [-360, 360]"},
    {"simulate --vin 2.9,-2.3", "--vin"},
    {"simulate --vin 2.9,-2.3,-65 --dt -1", "--dt"},
    // Within --dt's range but above the model's stability limit (issue 34): an input error too.
    {"simulate --vin 2.9,-2.3,-65 --dt 9e-4", "exceeds the stability limit"},
    {"simulate --vin 2.9,-2.3,-65 --set kr=1e10", "field 'dt_s'"},
    {"calibrate " + kCyl + " --starts 0", "field '--starts': value 0 is outside [1, 1000]"},
    {"calibrate " + kCyl + " --sigma 0.1,-1,3", "--sigma"},
    {"calibrate " + kCyl + " --threads -1", "--threads"},
    {"montecarlo --n -5", "--n: value -5 is outside [2, 1e+09]"},
    {"montecarlo --n 1", "field '--n': value 1 is outside [2, 1e+09]"},
    {"montecarlo --n many", "--n: 'many' is not a number"},
    {"montecarlo --alpha-range -200,60", "--alpha-range"},
    {"montecarlo --range-runs 0", "--range-runs"},
    {"sobol --confidence 1.5", "field '--confidence': value 1.5 is outside (0, 1)"},
    {"sobol --n 0", "--n"},
    {"sobol --bootstrap 0", "field '--bootstrap': value 0 is outside [2, 1e+06]"},
    {"synth --n 0 --out s.csv", "field '--n': value 0 is outside [1, 1e+07]"},
    {"compare " + kCyl + " --repeats 0", "field '--repeats': value 0 is outside [1, 20]"},
    {"compare " + kCyl + " --orientations -1", "--orientations"},
    {"compare " + kCyl + " --polish-orientations 1",
     "field '--polish-orientations': 1 is no average: 0 (no polish) or at least 2"},
    {"compare " + kCyl + " --orientation-search grid",
     "field '--orientation-search': 'grid': use multistart or surface"},
    {"diagnose " + kCyl + " --alpha 2", "field '--alpha': value 2 is outside (0, 1)"},
    {"diagnose " + kCyl + " --screen -1", "--screen"},
    {"ladder " + kCyl + " --auto 0", "--auto: value 0 is outside [1, 20]"},
    {"diagnose " + kCyl + " --where \"vin_x>100\"", "--where"},
    {"compare " + kCyl + " --where \"vin_x<<3\"", "--where"},
    {"ladder " + kCyl + " --threads 1e6", "--threads"},
    {"report " + kCyl + " --rounds 50 --out r.html",
     "field '--rounds': value 50 is outside [0, 20]"},
    {"dem template --out t --tolerance 5", "--tolerance: value 5 is outside [1e-07, 1]"},
    {"dem template --out t --length 0", "--length"},
    {"dem impact --alpha-deg 1000", "--alpha-deg"},
    {"dem impact --fps -1", "--fps"},
    {"dem bed --bogus", "--bogus"},
    {"dem campaign no-such-design.toml", "no-such-design.toml"},
    {"upscale no-such-campaign.h5", "no-such-campaign.h5"},
    {"upscale " + kCampaign + " --lab " + kCyl + " --lab-noise 0.1,-1,8",
     "--lab-noise: value -1 is outside [0, 1000]"},
    {"upscale " + kCampaign + " --lab " + kCyl + " --lab-noise 0.1,0.1", "--lab-noise"},
    {"upscale " + kCampaign + " --lab-noise 0.1,0.1,8", "--lab-noise"},
    {"upscale " + kCampaign + " --lab-where id==C01", "field '--lab-where': needs --lab"},
    {"upscale " + kCampaign + " --lab-same-ids", "field '--lab-same-ids': needs --lab"},
    {"upscale " + kCampaign + " --lab " + kCyl + " --lab-where id==C99",
     "field '--lab-where': 'id==C99' keeps no release"},
    {"calibrate-grains no-such-campaign.h5 --lab " + kCyl, "no-such-campaign.h5"},
    {"calibrate-grains " + kCyl, "--lab"},
    {"calibrate-grains " + kCampaign + " --lab " + kCyl + " --lab-where id==C99",
     "field '--lab-where': 'id==C99' keeps no release"},
    {"calibrate-grains " + kCampaign + " --lab " + kCyl + " --lab-where \"vinx<3\"",
     "--lab-where: field 'vinx<3': unknown feature"},
    {"calibrate-grains " + kCampaign + " --lab " + kCyl + " --rebound-threshold 1",
     "--rebound-threshold: value 1 is outside [0, 0.999]"},
};

class BadOptions : public test::ProgramTest, public ::testing::WithParamInterface<BadCase> {};

TEST_P(BadOptions, ExitTwoNamingTheOption) {
  const BadCase& c = GetParam();
  if (test::needs_liggghts(c.args) && !test::program_has_liggghts())
    GTEST_SKIP() << "this ricochet has no LIGGGHTS (WithoutLiggghts checks what it says)";
  const test::RunResult r = ricochet(c.args);
  EXPECT_EQ(r.status, 2) << c.args << "\n" << r.err;
  EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\nstderr: " << r.err;
  EXPECT_TRUE(r.out.empty()) << c.args << "\nstdout: " << r.out;
}

// Test names: the case's index and subcommand, e.g. 13_montecarlo.
std::string case_name(const ::testing::TestParamInfo<BadCase>& info) {
  const std::string& a = info.param.args;
  std::string sub = a.substr(0, a.find(' '));
  std::erase(sub, '-');  // GoogleTest names are alphanumeric: calibrate-grains -> calibrategrains
  return std::to_string(info.index) + "_" + sub;
}

INSTANTIATE_TEST_SUITE_P(EverySubcommand, BadOptions, ::testing::ValuesIn(kCases), case_name);

// The rule's other side: --help and --version succeed.
class GoodExits : public test::ProgramTest {};

TEST_F(GoodExits, HelpAndVersionExitZero) {
  for (const std::string args : {"--version", "--help", "montecarlo --help", "dem impact --help"}) {
    if (test::needs_liggghts(args) && !test::program_has_liggghts()) continue;
    const test::RunResult r = ricochet(args);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    EXPECT_FALSE(r.out.empty()) << args;
  }
}

// Every JSON document names the subcommand that made it and the program's version (print_json).
TEST_F(GoodExits, JsonNamesTheCommandAndVersion) {
  const std::vector<std::pair<std::string, std::string>> runs = {
      {"effects --json", "effects"},
      {"effects rolling --json", "effects"},
      {"simulate --vin 2.9,-2.3,-65 --json", "simulate"},
      {"stats " + kCyl + " --json", "stats"},
      {"transfer fit " + kCyl + " --json", "transfer fit"},
      {"dem template --shape cylinder --out " + quote((dir_ / "t").string()) + " --json",
       "dem template"}};
  for (const auto& [args, command] : runs) {
    if (test::needs_liggghts(args) && !test::program_has_liggghts()) continue;
    const test::RunResult r = ricochet(args);
    ASSERT_EQ(r.status, 0) << args << "\n" << r.err;
    const auto doc = nlohmann::json::parse(r.out);
    EXPECT_EQ(doc.value("command", ""), command) << args;
    EXPECT_EQ(doc.value("version", ""), RICOCHET_VERSION) << args;
  }
}

TEST_F(GoodExits, HelpShowsTheRange) {
  const test::RunResult r = ricochet("montecarlo --help");
  ASSERT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("in " + uq::MonteCarloOptions::kRuns.text()), std::string::npos) << r.out;
}

// effects --out: one CSV row per parameter of every effect (the --json document's count), the
// paper's kn as declared; or the JSON document itself.
TEST_F(GoodExits, EffectsOutWritesTheCatalog) {
  const auto csv = dir_ / "catalog.csv", json = dir_ / "catalog.json";
  ASSERT_EQ(ricochet("effects --out " + quote(csv.string())).status, 0);
  const test::RunResult r = ricochet("effects --json --out " + quote(json.string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  std::size_t parameters = 0;
  for (const auto& e : doc["effects"]) parameters += e["parameters"].size();
  ASSERT_GT(parameters, 40u);
  const std::string text = test::slurp(csv);
  std::size_t lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, parameters + 1) << text.substr(0, 300);
  EXPECT_EQ(text.rfind("effect,stage,generated,parameter,unit,lower,upper,nominal,neutral,", 0),
            0u);
  EXPECT_NE(text.find("\nnormal,normal,0,kn,N/m,1e+05,1e+09,1e+07,,0,"), std::string::npos)
      << text.substr(0, 600);
  EXPECT_EQ(nlohmann::json::parse(test::slurp(json))["effects"], doc["effects"]);
}

// A build without LIGGGHTS keeps the resolved model's subcommands: whatever their arguments, they
// exit with the runtime-failure status 1, say what is missing and how to get it, and print
// nothing on stdout; --help still works.
TEST_F(GoodExits, WithoutLiggghtsTheResolvedModelSaysHowToGetIt) {
  if (test::program_has_liggghts()) GTEST_SKIP() << "this ricochet has LIGGGHTS";
  const std::vector<std::string> runs = {
      "dem", "dem impact --alpha-deg 30 --json", "dem campaign design.toml --out c.h5",
      "upscale campaign.h5 --lab " + kCyl, "calibrate-grains campaign.h5 --lab " + kCyl};
  for (const std::string& args : runs) {
    const test::RunResult r = ricochet(args);
    EXPECT_EQ(r.status, 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("needs LIGGGHTS, and this build of ricochet has none"), std::string::npos)
        << args << "\n"
        << r.err;
    EXPECT_NE(r.err.find("apt install liggghts libliggghts-dev"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("-DRICOCHET_WITH_LIGGGHTS=ON"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << args << "\nstdout: " << r.out;
  }
  const test::RunResult help = ricochet("--help");
  ASSERT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("no LIGGGHTS"), std::string::npos) << help.out;
}

// --where on the diagnosis commands keeps only the matching releases (as stats does).
TEST_F(GoodExits, CompareReadsOnlyTheReleasesWhereSelects) {
  const test::RunResult all = ricochet("compare " + kCyl + " --json");
  const test::RunResult some = ricochet("compare " + kCyl + " --where \"vin_x<3\" --json");
  ASSERT_EQ(all.status, 0) << all.err;
  ASSERT_EQ(some.status, 0) << some.err;
  const auto a = nlohmann::json::parse(all.out), b = nlohmann::json::parse(some.out);
  const test::RunResult stats = ricochet("stats " + kCyl + " --where \"vin_x<3\" --json");
  ASSERT_EQ(stats.status, 0) << stats.err;
  const std::size_t expected = nlohmann::json::parse(stats.out)["n"].get<std::size_t>();
  ASSERT_EQ(a["releases"].size(), 28u);
  ASSERT_GT(expected, 0u);
  ASSERT_LT(expected, 28u);
  ASSERT_EQ(b["releases"].size(), expected);
  std::set<std::string> ids;
  for (const auto& r : a["releases"]) ids.insert(r["id"].get<std::string>());
  for (const auto& r : b["releases"]) EXPECT_TRUE(ids.count(r["id"].get<std::string>())) << r["id"];
}

}  // namespace
}  // namespace ricochet
