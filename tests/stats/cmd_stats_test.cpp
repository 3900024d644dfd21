// Runs the built `ricochet stats` program on the embedded lab data and checks its JSON, its
// files and its errors. RICOCHET_EXE is the program's path (set by CMake).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "common/h5.hpp"
#include "impact/block_track.hpp"
#include "impact/impact_set.hpp"
#include "support/program_test.hpp"
#include "table2.hpp"

namespace ricochet {
namespace {

using test::quote;
using test::RunResult;
using test::slurp;
using Result = test::RunResult;

namespace fs = std::filesystem;
const std::string kSource = RICOCHET_SOURCE_DIR;
const std::string kLab = kSource + "/data/lab/";

class CmdStats : public test::ProgramTest {
 protected:
};

template <typename Table>
void expect_table2_json(const nlohmann::json& doc, const Table& table) {
  for (const auto& p : table) {
    ASSERT_TRUE(doc["columns"].contains(p.name)) << p.name;
    const auto& c = doc["columns"][p.name];
    test::expect_table2_column(p, c["mean"], c["std"], c["cv"], c["min"], c["max"]);
    EXPECT_EQ(c["unit"], p.name[0] == 'w' ? "rad/s" : "m/s");
  }
}

TEST_F(CmdStats, JsonReproducesTable2ForCylinders) {
  const RunResult run = ricochet("stats --json " + quote(kLab + "cylinders.csv"));
  ASSERT_EQ(run.status, 0) << run.err;
  const auto doc = nlohmann::json::parse(run.out);  // stdout is one JSON document, nothing else
  EXPECT_EQ(doc["source"], kLab + "cylinders.csv");
  EXPECT_EQ(doc["n"], 28);
  EXPECT_TRUE(doc["where"].is_null());
  EXPECT_EQ(doc["columns"].size(), 6u);
  expect_table2_json(doc, test::kTable2Cylinders);
}

TEST_F(CmdStats, JsonReproducesTable2ForAll31Triangles) {
  const RunResult run = ricochet("stats " + quote(kLab + "triangles.csv") + " --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const auto doc = nlohmann::json::parse(run.out);
  EXPECT_EQ(doc["n"], 31);
  expect_table2_json(doc, test::kTable2Triangles);
}

TEST_F(CmdStats, WhereSelectsReleases) {
  const RunResult run =
      ricochet("stats --json --where 'vin_x<3.5' " + quote(kLab + "triangles.csv"));
  ASSERT_EQ(run.status, 0) << run.err;
  const auto doc = nlohmann::json::parse(run.out);
  EXPECT_EQ(doc["n"], 19);
  EXPECT_EQ(doc["where"], "vin_x<3.5");
  EXPECT_LT(doc["columns"]["vin_x"]["max"].get<double>(), 3.5);
}

TEST_F(CmdStats, TableOnTerminalOutput) {
  const RunResult run = ricochet("stats " + quote(kLab + "cylinders.csv"));
  ASSERT_EQ(run.status, 0) << run.err;
  for (const char* s : {"28 releases", "V_in^x", "omega_out", "mean", "std", "cv [%]", "min", "max",
                        "-77.82", "3.055"})
    EXPECT_NE(run.out.find(s), std::string::npos) << s << "\n" << run.out;
}

TEST_F(CmdStats, OutWritesCsvAndHdf5) {
  const std::string csv = (dir_ / "stats.csv").string();
  const std::string h5 = (dir_ / "stats.h5").string();
  const RunResult a =
      ricochet("stats --json --out " + quote(csv) + " " + quote(kLab + "cylinders.csv"));
  ASSERT_EQ(a.status, 0) << a.err;
  const auto doc = nlohmann::json::parse(a.out);
  const std::string text = slurp(csv);
  EXPECT_NE(text.find("column,unit,n,mean,std,cv,min,max\n"), std::string::npos);
  EXPECT_NE(text.find("\nwout,rad/s,28,"), std::string::npos) << text;

  const RunResult b = ricochet("stats --out " + quote(h5) + " " + quote(kLab + "cylinders.csv"));
  ASSERT_EQ(b.status, 0) << b.err;
  h5::File f(h5, h5::File::Mode::kRead);
  const auto names = f.read_strings("/stats/column");
  const auto mean = f.read_doubles("/stats/mean");
  ASSERT_EQ(names.size(), 6u);
  EXPECT_EQ(names, (std::vector<std::string>{"vin_x", "vout_x", "vin_y", "vout_y", "win", "wout"}));
  for (std::size_t k = 0; k < names.size(); ++k)
    EXPECT_EQ(mean[k], doc["columns"][names[k]]["mean"].get<double>()) << names[k];
}

TEST_F(CmdStats, BadInputExitsWithTwoAndNamesTheCell) {
  const fs::path bad = dir_ / "bad.csv";
  std::ofstream(bad) << "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],"
                        "wout[rad/s]\nA,cylinder,1,-1,-10,1,0.5,-5\nB,cylinder,1,-1,-10,1,x,-5\n";
  const RunResult run = ricochet("stats --json " + quote(bad.string()));
  EXPECT_EQ(run.status, 2);
  EXPECT_TRUE(run.out.empty()) << run.out;
  EXPECT_NE(run.err.find(bad.string() + ":3: field 'vout_y'"), std::string::npos) << run.err;

  const RunResult where = ricochet("stats --where 'vinx<3' " + quote(kLab + "cylinders.csv"));
  EXPECT_EQ(where.status, 2);
  EXPECT_NE(where.err.find("vinx<3"), std::string::npos) << where.err;

  const RunResult none = ricochet("stats --where 'vin_x>100' " + quote(kLab + "cylinders.csv"));
  EXPECT_EQ(none.status, 2);

  const RunResult ext = ricochet("stats --out " + quote((dir_ / "x.txt").string()) + " " +
                                 quote(kLab + "cylinders.csv"));
  EXPECT_EQ(ext.status, 2);
  EXPECT_FALSE(fs::exists(dir_ / "x.txt"));
}

// A campaign-like file: /impacts with the lab's C01 and C02, a track for C01 and one for an impact
// not in the set (a failed run). C01's force: 0, 0, 0, 100, 200, 300, 200, 100, 0, 0, 0 N every 1
// ms, its block 1 kg (0.2 m g = 1.962 N), its penetration peaking at 4 mm and 2.5 mm at the end of
// the force.
std::string campaign_file(const fs::path& dir, bool malformed) {
  const std::string path = (dir / "campaign.h5").string();
  ImpactSet set = read_impact_set(kLab + "cylinders.csv");
  set.impacts.resize(2);
  write_impact_set_h5(set, path);
  BlockTrack tr;
  const double force[] = {0, 0, 0, 100, 200, 300, 200, 100, 0, 0, 0};
  const double pen[] = {-3, -2, -1, 1, 3, 4, 3.5, 2.5, 1, -1, -3};
  for (int k = 0; k < 11; ++k) {
    tr.t.push_back(1e-3 * k);
    tr.fcy.push_back(force[k]);
    tr.fcx.push_back(-force[k] / 2);
    tr.penetration.push_back(1e-3 * pen[k]);
  }
  tr.pad();
  tr.block_mass_kg = 1.0;
  write_block_track(path, "C01", tr);
  write_block_track(path, "F01", tr);
  if (malformed) {
    h5::File f(path, h5::File::Mode::kReadWrite);
    // Replaced without its attribute: read as the first campaigns' twelve columns.
    f.write("/dem/tracks/C01", std::vector<double>(6, 0.0), {2, 3});
  }
  return path;
}

TEST_F(CmdStats, SummarisesTheTracksOfACampaignFile) {
  const std::string path = campaign_file(dir_, false);
  const RunResult run = ricochet("stats --json " + quote(path));
  ASSERT_EQ(run.status, 0) << run.err;
  const auto doc = nlohmann::json::parse(run.out);
  const auto& t = doc["tracks"];
  EXPECT_EQ(t["releases"], 2);
  EXPECT_EQ(t["with_track"], 1);
  EXPECT_EQ(t["other_tracks"], 1);
  ASSERT_EQ(t["impacts"].size(), 1u);
  const auto& c = t["impacts"][0];
  EXPECT_EQ(c["id"], "C01");
  EXPECT_EQ(c["records"], 11);
  EXPECT_NEAR(c["contact_start"].get<double>(), 0.003, 1e-12);
  EXPECT_NEAR(c["contact_end"].get<double>(), 0.007, 1e-12);
  EXPECT_NEAR(c["contact_duration"].get<double>(), 0.004, 1e-12);
  EXPECT_DOUBLE_EQ(c["peak_normal_force"].get<double>(), 300.0);
  EXPECT_DOUBLE_EQ(c["peak_tangential_force"].get<double>(), 150.0);
  EXPECT_TRUE(c["peak_torque"].is_null());  // NaN throughout
  EXPECT_NEAR(c["max_penetration"].get<double>(), 0.004, 1e-15);
  EXPECT_NEAR(c["elastic_recovery"].get<double>(), 0.0015, 1e-15);
  EXPECT_EQ(c["block_mass_source"], "file");
  EXPECT_EQ(t["summary"]["peak_normal_force"]["n"], 1);

  const RunResult text = ricochet("stats " + quote(path));
  ASSERT_EQ(text.status, 0) << text.err;
  for (const char* s : {"Tracks (/dem/tracks): 1 of 2 releases", "1 more of impacts not in this",
                        "contact duration [ms]", "peak |torque| [N*m]"})
    EXPECT_NE(text.out.find(s), std::string::npos) << s << "\n" << text.out;
  // A set without tracks says nothing of them.
  const RunResult lab = ricochet("stats --json " + quote(kLab + "cylinders.csv"));
  EXPECT_TRUE(nlohmann::json::parse(lab.out)["tracks"].is_null());
}

// A campaign file's outcomes: its index says C01 rebounded, T01 timed out and T02 was refused.
// The captured T01's track ends at t = 0.3 s moving at (0.3, -0.4) m/s, 6 mm below the level:
// the outcome gives that last record (|v| = 0.5 m/s); the refused T02, with a track too, is not
// captured and gets none.
TEST_F(CmdStats, OutcomesSayWhereACapturedTrackEnds) {
  const std::string path = campaign_file(dir_, false);
  {
    h5::File f(path, h5::File::Mode::kReadWrite);
    f.write_strings("/dem/index/id", {"C01", "T01", "T02"});
    f.write_strings("/dem/index/status", {"rebound", "timeout", "invalid"});
    f.write_strings("/dem/index/shape", {"cylinder", "triangle", "triangle"});
    f.write_strings("/dem/index/params", {"{}", R"({"vin": [3.0, -2.0, -20.0]})", "{}"});
  }
  BlockTrack tr;
  for (int k = 0; k <= 3; ++k) {
    tr.t.push_back(0.1 * k);
    tr.vx.push_back(k == 3 ? 0.3 : 1.0);
    tr.vy.push_back(k == 3 ? -0.4 : 0.0);
    tr.w.push_back(k == 3 ? -2.5 : -10.0);
    tr.penetration.push_back(k == 3 ? 0.006 : 0.0);
    tr.ke_block.push_back(k == 3 ? 1.25 : 10.0);
  }
  tr.pad();
  write_block_track(path, "T01", tr);
  write_block_track(path, "T02", tr);
  const RunResult run = ricochet("stats --json " + quote(path));
  ASSERT_EQ(run.status, 0) << run.err;
  const auto oc = nlohmann::json::parse(run.out)["outcomes"];
  EXPECT_EQ(oc["captured"], 1);
  EXPECT_EQ(oc["ran"], 2);
  ASSERT_EQ(oc["captured_ends"].size(), 1u) << oc.dump();
  const auto& e = oc["captured_ends"][0];
  EXPECT_EQ(e["id"], "T01");
  EXPECT_EQ(e["status"], "timeout");
  EXPECT_DOUBLE_EQ(e["t"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(e["speed"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(e["spin"].get<double>(), -2.5);
  EXPECT_DOUBLE_EQ(e["penetration"].get<double>(), 0.006);
  EXPECT_DOUBLE_EQ(e["ke_block"].get<double>(), 1.25);
  const RunResult text = ricochet("stats " + quote(path));
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("T01 (timeout): t = 0.300 s, |v| = 0.500 m/s, omega = -2.50 rad/s, "
                          "lowest point 6.0 mm"),
            std::string::npos)
      << text.out;
}

TEST_F(CmdStats, AMalformedTrackExitsWithTwoAndNamesTheFileAndTheTrack) {
  const std::string path = campaign_file(dir_, true);
  const RunResult run = ricochet("stats " + quote(path));
  EXPECT_EQ(run.status, 2) << run.out;
  EXPECT_NE(run.err.find(path + ": field '/dem/tracks/C01'"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("2 x 3"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace ricochet
