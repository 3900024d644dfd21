// The --out and --json contract of docs/commands/ over every subcommand:
// - --out: an extension outside the command's list is refused (status 2) with a message listing
//   the accepted ones, before any work; each accepted extension writes a file of that format, in
//   one piece (no temporary left behind);
// - --json: every document carries the provenance of its inputs, whose hash is checked against an
//   independent FNV-1a implementation, and every top-level key is documented in the "JSON keys"
//   section of the command's page (a key added without its documentation fails, naming both).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>
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

struct OutCase {
  std::string args;                   // after `ricochet`, without --out
  std::vector<std::string> accepted;  // the extensions of docs/commands/README.md, in its order
  bool write = true;  // also write every accepted extension (the commands that take seconds)
};

void PrintTo(const OutCase& c, std::ostream* os) {
  *os << c.args;
}

const std::vector<std::string> kTable = {".csv", ".h5", ".hdf5", ".json"};
// Where --out names the command's primary artifact, .json is refused.
const std::vector<std::string> kImpactSet = {".csv", ".h5", ".hdf5"};

// One case per subcommand with --out (dem template's --out is a prefix and dem bed has none:
// docs/commands/README.md says so).
const std::vector<OutCase> kCases = {
    {"stats " + kCyl, kTable},
    {"paired " + quote(kSource + "/data/resolved/stiffness-plateau.h5") +
         " --base E1.5e7- --against E1.5e8-",
     {".csv", ".json"}},
    {"reconstruct no-such-track.csv", kTable, false},
    {"transfer fit " + kCyl, kTable},
    {"transfer predict --seed 1 --from " + kCyl + " --vin 2.9,-2.3,-65", kTable},
    {"effects", {".csv", ".json"}},
    {"simulate --vin 2.9,-2.3,-65", kTable},
    {"calibrate " + kCyl + " --where \"vin_x>3.1\"", kTable},
    {"montecarlo --n 200 --seed 3", kTable},
    {"sobol --n 32 --bootstrap 10", {".h5", ".hdf5", ".json"}},
    {"synth --n 4 --seed 5", kImpactSet},
    {"compare " + kCyl + " --repeats 1", kTable},
    {"diagnose " + kCyl, kTable, false},
    {"ladder " + kCyl, kTable, false},
    {"report " + kCyl, {".html", ".htm"}, false},
    {"dem impact", {".h5", ".hdf5", ".csv", ".json"}, false},
    {"dem campaign " + quote(kSource + "/liggghts-inputs/campaigns/main-job.toml"),
     {".h5", ".hdf5"},
     false},
    {"dem drop", {".csv"}, false},
    {"dem repose", {".json"}, false},
    {"upscale " + quote(kSource + "/data/resolved/bed-probe-width-cdt.h5"),
     {".h5", ".hdf5", ".json"}},
    {"calibrate-grains " + quote(kSource + "/data/resolved/bed-calibration-cdt.h5") + " --lab " +
         kCyl,
     {".json"}},
};

class OutContract : public test::ProgramTest, public ::testing::WithParamInterface<OutCase> {};
class OutWrites : public OutContract {};

TEST_P(OutContract, AnUnknownExtensionIsRefusedWithTheAcceptedOnes) {
  const OutCase& c = GetParam();
  if (test::needs_liggghts(c.args) && !test::program_has_liggghts())
    GTEST_SKIP() << "this ricochet has no LIGGGHTS";
  const fs::path bad = dir_ / "result.bogus";
  const test::RunResult r = ricochet(c.args + " --out " + quote(bad.string()));
  EXPECT_EQ(r.status, 2) << c.args << "\n" << r.err;
  std::string list;
  for (const auto& e : c.accepted) list += (list.empty() ? "" : ", ") + e;
  EXPECT_NE(r.err.find("field '--out': unsupported file extension; use one of " + list),
            std::string::npos)
      << c.args << "\nstderr: " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_FALSE(fs::exists(bad));
}

// The cells of one CSV line, quotes respected ("a,b" is one cell; "" inside quotes is a quote).
std::size_t count_cells(const std::string& line) {
  std::size_t cells = 1;
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') quoted = !quoted;
    if (ch == ',' && !quoted) ++cells;
  }
  return cells;
}

// The format of a written file, from its first bytes.
void expect_format(const fs::path& file, const std::string& ext, const std::string& args) {
  ASSERT_TRUE(fs::exists(file)) << args << " did not write " << file;
  const std::string text = test::slurp(file);
  ASSERT_FALSE(text.empty()) << file;
  if (ext == ".h5" || ext == ".hdf5") {
    EXPECT_EQ(text.substr(0, 8), std::string("\x89HDF\r\n\x1a\n", 8)) << file << ": not HDF5";
  } else if (ext == ".json") {
    const auto doc = nlohmann::json::parse(text);
    EXPECT_TRUE(doc.contains("command")) << file;
  } else if (ext == ".csv") {
    // After the '#' comments: a header of several cells and at least one row of as many.
    std::istringstream in(text);
    std::string line, header;
    std::size_t rows = 0;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (header.empty()) {
        header = line;
        continue;
      }
      ++rows;
      EXPECT_EQ(count_cells(line), count_cells(header))
          << file << ": row " << rows << " has another number of cells than the header";
    }
    EXPECT_GT(count_cells(header), 1u) << file;
    EXPECT_GT(rows, 0u) << file;
  }
}

TEST_P(OutWrites, EveryAcceptedExtensionWritesThatFormatInOnePiece) {
  const OutCase& c = GetParam();
  if (test::needs_liggghts(c.args) && !test::program_has_liggghts())
    GTEST_SKIP() << "this ricochet has no LIGGGHTS";
  for (const auto& ext : c.accepted) {
    const fs::path out = dir_ / ("result" + ext);
    const test::RunResult r = ricochet(c.args + " --out " + quote(out.string()));
    ASSERT_EQ(r.status, 0) << c.args << " --out " << out << "\n" << r.err;
    expect_format(out, ext, c.args);
  }
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_NE(entry.path().extension(), ".tmp") << "left behind: " << entry.path();
}

std::string case_name(const ::testing::TestParamInfo<OutCase>& info) {
  std::string sub = info.param.args.substr(0, info.param.args.find(" -"));
  sub = sub.substr(0, sub.find(" '"));
  std::string name = std::to_string(info.index) + "_";
  for (char ch : sub)
    if (std::isalnum(static_cast<unsigned char>(ch))) name += ch;
  return name;
}

// The slower commands (diagnose, ladder, report, LIGGGHTS runs) write their files in their own
// tests; here they are only refused.
std::vector<OutCase> write_cases() {
  std::vector<OutCase> cases;
  for (const auto& c : kCases)
    if (c.write) cases.push_back(c);
  return cases;
}

INSTANTIATE_TEST_SUITE_P(EverySubcommand, OutContract, ::testing::ValuesIn(kCases), case_name);
INSTANTIATE_TEST_SUITE_P(FastSubcommands, OutWrites, ::testing::ValuesIn(write_cases()), case_name);

// FNV-1a 64, written here from the published definition (offset basis 14695981039346656037,
// prime 1099511628211) rather than taken from the program.
std::string fnv1a64_hex(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char ch : bytes) {
    h ^= ch;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

class Provenance : public test::ProgramTest {};

TEST_F(Provenance, ReferenceHashMatchesThePublishedVectors) {
  // Test vectors of the FNV reference (Fowler, Noll, Vo; draft-eastlake-fnv): "" and "a", "foobar".
  EXPECT_EQ(fnv1a64_hex(""), "cbf29ce484222325");
  EXPECT_EQ(fnv1a64_hex("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(fnv1a64_hex("foobar"), "85944171f73967e8");
}

// Every JSON document lists the files it read with their size and content hash; a changed file
// changes the hash, the files written (--out) are not listed.
TEST_F(Provenance, JsonListsTheInputFilesWithTheirContentHash) {
  const fs::path data = dir_ / "set.csv";
  fs::copy_file(kSource + "/data/lab/cylinders.csv", data);
  const auto run = [&]() {
    const test::RunResult r = ricochet("stats " + quote(data.string()) + " --json --out " +
                                       quote((dir_ / "s.h5").string()));
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(r.out);
  };
  const auto doc = run();
  ASSERT_EQ(doc["input_files"].size(), 1u) << doc["input_files"].dump();
  const auto& in = doc["input_files"][0];
  const std::string bytes = test::slurp(data);
  EXPECT_EQ(in["file"], data.string());
  EXPECT_EQ(in["option"], "DATA");
  EXPECT_EQ(in["bytes"].get<std::size_t>(), bytes.size());
  EXPECT_EQ(in["fnv1a64"], fnv1a64_hex(bytes));

  std::ofstream(data, std::ios::app) << "\n";
  const auto changed = run();
  EXPECT_NE(changed["input_files"][0]["fnv1a64"], in["fnv1a64"]);
  EXPECT_EQ(changed["input_files"][0]["fnv1a64"], fnv1a64_hex(test::slurp(data)));

  // A command with two inputs lists both, in option order.
  const test::RunResult two = ricochet("montecarlo --n 50 --compare " + quote(data.string()) +
                                       " --incident " + kCyl + " --json");
  ASSERT_EQ(two.status, 0) << two.err;
  const auto files = nlohmann::json::parse(two.out)["input_files"];
  ASSERT_EQ(files.size(), 2u) << files.dump();
}

// --- --out FILE.json: the --json document, in a file ---

class JsonFile : public test::ProgramTest {};

// `--out FILE.json` writes exactly the document `--json` prints (with "out" naming the file) and
// says so on stdout; with --json as well it also prints it. Nothing else is written.
TEST_F(JsonFile, OutJsonIsTheJsonDocumentInAFile) {
  const std::string args = "transfer fit " + kCyl + " --seed 4 --replicates 20";
  const test::RunResult printed = ricochet(args + " --json");
  ASSERT_EQ(printed.status, 0) << printed.err;
  auto expected = nlohmann::json::parse(printed.out);

  const fs::path file = dir_ / "fit.json";
  const test::RunResult quiet = ricochet(args + " --out " + quote(file.string()));
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_EQ(quiet.out, "wrote " + file.string() + "\n");
  auto written = nlohmann::json::parse(test::slurp(file));
  EXPECT_EQ(written["out"], file.string());
  ASSERT_TRUE(expected.contains("out"));
  expected["out"] = file.string();
  EXPECT_EQ(written, expected);

  const fs::path both = dir_ / "both.json";
  const test::RunResult loud = ricochet(args + " --json --out " + quote(both.string()));
  ASSERT_EQ(loud.status, 0) << loud.err;
  EXPECT_EQ(nlohmann::json::parse(loud.out), nlohmann::json::parse(test::slurp(both)));
  std::size_t files = 0;  // the harness keeps the runs' stderr in dir_ as .txt
  for (const auto& entry : fs::directory_iterator(dir_)) {
    if (entry.path().extension() == ".txt") continue;
    ++files;
    EXPECT_EQ(entry.path().extension(), ".json") << "unexpected: " << entry.path();
  }
  EXPECT_EQ(files, 2u);
}

// Where --out names the command's artifact (the impact set of synth), .json is refused: the
// command would otherwise finish without its artifact.
TEST_F(JsonFile, RefusedWhereOutIsTheArtifact) {
  const fs::path file = dir_ / "set.json";
  const test::RunResult r = ricochet("synth --n 4 --seed 5 --out " + quote(file.string()));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("use one of .csv, .h5, .hdf5"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(file));
}

// --- JSON keys against docs/commands/ ---

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

class JsonKeys : public test::ProgramTest, public ::testing::WithParamInterface<KeysCase> {};

TEST_P(JsonKeys, EveryTopLevelKeyIsDocumented) {
  KeysCase c = GetParam();
  if (test::needs_liggghts(c.args) && !test::program_has_liggghts())
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

const std::vector<KeysCase> kKeysCases = {
    {"stats " + kCyl, "stats"},
    {"paired " + quote(kSource + "/data/resolved/stiffness-plateau.h5") +
         " --base E1.5e7- --against E1.5e8-",
     "paired"},
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

std::string keys_case_name(const ::testing::TestParamInfo<KeysCase>& info) {
  std::string name = std::to_string(info.index) + "_";
  for (char ch : info.param.page)
    if (std::isalnum(static_cast<unsigned char>(ch))) name += ch;
  return name;
}

INSTANTIATE_TEST_SUITE_P(EverySubcommand, JsonKeys, ::testing::ValuesIn(kKeysCases),
                         keys_case_name);

}  // namespace
}  // namespace ricochet
