// docs/commands/ against the program: every top-level key of a subcommand's --json document is
// documented in the "JSON keys" section of the subcommand's page (or, for the keys every document
// carries, in docs/commands/README.md). A key added to a command without its documentation fails
// here, with the key and the page named.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "kinematics/synthetic_track.hpp"
#include "support/program_test.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
using test::quote;

const std::string kSource = RICOCHET_SOURCE_DIR;
const std::string kCyl = quote(kSource + "/data/lab/cylinders.csv");

struct KeysCase {
  std::string args;  // after `ricochet`, without --json
  std::string page;  // docs/commands/PAGE.md
};

void PrintTo(const KeysCase& c, std::ostream* os) {
  *os << c.args;
}

// The "JSON keys" section of a page: from its heading to the next "## " heading.
std::string json_section(const std::string& page) {
  const std::string text = test::slurp(kSource + "/docs/commands/" + page + ".md");
  std::size_t start = text.find("## JSON keys");
  if (start == std::string::npos) return {};
  const std::size_t end = text.find("\n## ", start + 1);
  return text.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

// Whether `key` is named in `text` as `key` or `key.member` (code) or "key" (JSON example).
bool names(const std::string& text, const std::string& key) {
  return text.find("`" + key + "`") != std::string::npos ||
         text.find("`" + key + ".") != std::string::npos ||
         text.find("\"" + key + "\"") != std::string::npos;
}

bool needs_liggghts(const std::string& args) {
  for (const char* sub : {"dem", "upscale", "calibrate-grains"})
    if (args.rfind(std::string(sub) + " ", 0) == 0) return true;
  return false;
}

class JsonKeys : public test::ProgramTest, public ::testing::WithParamInterface<KeysCase> {};

TEST_P(JsonKeys, EveryTopLevelKeyIsDocumented) {
  KeysCase c = GetParam();
  if (needs_liggghts(c.args) && !test::program_has_liggghts())
    GTEST_SKIP() << "this ricochet has no LIGGGHTS";
  for (std::size_t at; (at = c.args.find("@DIR@")) != std::string::npos;)
    c.args.replace(at, 5, dir_.string());
  // A synthetic video track (tests/kinematics), for reconstruct.
  std::ofstream(dir_ / "track.csv") << test::SyntheticImpact{}.csv(400, 0.14, 1e-3, 0.7, 5);
  const std::string section = json_section(c.page);
  ASSERT_FALSE(section.empty()) << "docs/commands/" << c.page << ".md has no \"## JSON keys\"";
  const std::string common = test::slurp(kSource + "/docs/commands/README.md");

  const test::RunResult r = ricochet(c.args + " --json");
  ASSERT_EQ(r.status, 0) << c.args << "\n" << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_TRUE(doc.is_object());
  ASSERT_GE(doc.size(), 4u) << r.out;  // command, version, input_files and the command's own
  for (const auto& [key, value] : doc.items()) {
    const bool everywhere = key == "command" || key == "version" || key == "input_files";
    EXPECT_TRUE(everywhere ? names(common, key) : names(section, key))
        << "key \"" << key << "\" of `ricochet " << c.args << " --json` is not documented in "
        << (everywhere ? "docs/commands/README.md" : "docs/commands/" + c.page + ".md, JSON keys");
  }
}

const std::vector<KeysCase> kCases = {
    {"stats " + kCyl, "stats"},
    {"reconstruct @DIR@/track.csv --pixel-size 0.001", "reconstruct"},
    {"transfer fit " + kCyl, "transfer"},
    {"transfer predict --seed 1 --from " + kCyl + " --vin 2.9,-2.3,-65", "transfer"},
    {"effects", "effects"},
    {"simulate --vin 2.9,-2.3,-65", "simulate"},
    {"calibrate " + kCyl + " --where \"vin_x>3.1\"", "calibrate"},
    {"montecarlo --n 200 --seed 3 --compare " + kCyl, "montecarlo"},
    {"sobol --n 32 --bootstrap 10", "sobol"},
    {"synth --n 4 --seed 5 --out @DIR@/s.csv", "synth"},
    {"compare " + kCyl + " --repeats 1", "compare"},
    {"diagnose " + kCyl, "diagnose"},
    {"ladder " + kCyl + " --add rate_restitution", "ladder"},
    {"report " + kCyl + " --out @DIR@/r.html", "report"},
    {"dem template --shape cylinder --out @DIR@/t", "dem"},
    {"upscale " + quote(kSource + "/data/resolved/bed-probe-width-cdt.h5"), "upscale"},
    {"calibrate-grains " + quote(kSource + "/data/resolved/bed-calibration-cdt.h5") + " --lab " +
         kCyl,
     "calibrate-grains"},
};

std::string case_name(const ::testing::TestParamInfo<KeysCase>& info) {
  std::string name = std::to_string(info.index) + "_";
  for (char ch : info.param.page)
    if (std::isalnum(static_cast<unsigned char>(ch))) name += ch;
  return name;
}

INSTANTIATE_TEST_SUITE_P(EverySubcommand, JsonKeys, ::testing::ValuesIn(kCases), case_name);

}  // namespace
}  // namespace ricochet
