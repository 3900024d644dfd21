// The --out and --json contract of docs/commands/README.md over every subcommand that writes a
// file: an extension outside the command's list is refused (status 2) with a message listing the
// accepted ones, before any work; each accepted extension writes a file of that format, in one
// piece (no temporary left behind); every JSON document carries the provenance of its inputs,
// whose hash is checked against an independent FNV-1a implementation.
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

const std::vector<std::string> kTable = {".csv", ".h5", ".hdf5"};

// One case per subcommand with --out (dem template's --out is a prefix and dem bed has none:
// docs/commands/README.md says so).
const std::vector<OutCase> kCases = {
    {"stats " + kCyl, kTable},
    {"reconstruct no-such-track.csv", kTable, false},
    {"transfer fit " + kCyl, kTable},
    {"transfer predict --seed 1 --from " + kCyl + " --vin 2.9,-2.3,-65", kTable},
    {"effects", {".csv", ".json"}},
    {"simulate --vin 2.9,-2.3,-65", kTable},
    {"calibrate " + kCyl + " --where \"vin_x>3.1\"", kTable},
    {"montecarlo --n 200 --seed 3", kTable},
    {"sobol --n 32 --bootstrap 10", {".h5", ".hdf5"}},
    {"synth --n 4 --seed 5", kTable},
    {"compare " + kCyl + " --repeats 1", kTable},
    {"diagnose " + kCyl, kTable, false},
    {"ladder " + kCyl, kTable, false},
    {"report " + kCyl, {".html", ".htm"}, false},
    {"dem impact", {".h5", ".hdf5", ".csv"}, false},
    {"dem campaign " + quote(kSource + "/liggghts-inputs/campaigns/main-job.toml"),
     {".h5", ".hdf5"},
     false},
    {"dem drop", {".csv"}, false},
    {"upscale " + quote(kSource + "/data/resolved/bed-probe-width-cdt.h5"), {".h5", ".hdf5"}},
    {"calibrate-grains " + quote(kSource + "/data/resolved/bed-calibration-cdt.h5") + " --lab " +
         kCyl,
     {".json"}},
};

bool needs_liggghts(const std::string& args) {
  for (const char* sub : {"dem", "upscale", "calibrate-grains"})
    if (args.rfind(std::string(sub) + " ", 0) == 0) return true;
  return false;
}

class OutContract : public test::ProgramTest, public ::testing::WithParamInterface<OutCase> {};
class OutWrites : public OutContract {};

TEST_P(OutContract, AnUnknownExtensionIsRefusedWithTheAcceptedOnes) {
  const OutCase& c = GetParam();
  if (needs_liggghts(c.args) && !test::program_has_liggghts())
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
  if (needs_liggghts(c.args) && !test::program_has_liggghts())
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

}  // namespace
}  // namespace ricochet
