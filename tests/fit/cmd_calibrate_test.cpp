// Runs the built `ricochet calibrate` program and checks its JSON contract, its files and its
// errors. RICOCHET_EXE is the program's path (set by CMake).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "common/h5.hpp"
#include "support/program_test.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
using test::quote;
using test::RunResult;
const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

class CmdCalibrate : public test::ProgramTest {};

TEST_F(CmdCalibrate, JsonContract) {
  const std::string h5 = (dir_ / "cal.h5").string();
  const RunResult run = ricochet("calibrate " + quote(kLab + "cylinders.csv") +
                                 " --shape cylinder --seed 3 --starts 3 --where 'vin_x>2.9'"
                                 " --json --out " +
                                 quote(h5) + " --figures " + quote((dir_ / "fig").string()));
  ASSERT_EQ(run.status, 0) << run.err;
  const auto doc = nlohmann::json::parse(run.out);  // one JSON document on stdout
  ASSERT_TRUE(doc.contains("releases"));
  ASSERT_TRUE(doc.contains("summary"));
  ASSERT_TRUE(doc["seconds"].is_number());
  EXPECT_GT(doc["releases"].size(), 5u);
  for (const auto& r : doc["releases"]) {
    ASSERT_TRUE(r["id"].is_string());
    ASSERT_TRUE(r["error"].is_number());
    for (const char* p : {"en2", "mu", "muR"}) {
      ASSERT_TRUE(r["params"][p].is_number()) << p;
      ASSERT_EQ(r["intervals"][p].size(), 2u) << p;
      EXPECT_LE(r["intervals"][p][0].get<double>(), r["params"][p].get<double>() + 1e-12);
      EXPECT_GE(r["intervals"][p][1].get<double>(), r["params"][p].get<double>() - 1e-12);
      EXPECT_TRUE(r["identifiability"][p].is_string());
    }
  }
  for (const char* p : {"en2", "mu", "muR"}) {
    EXPECT_TRUE(doc["summary"][p]["mean"].is_number()) << p;
    EXPECT_TRUE(doc["summary"][p]["std"].is_number()) << p;
  }
  EXPECT_EQ(doc["settings"]["seed"], 3);
  EXPECT_EQ(doc["settings"]["starts"], 3);
  // The HDF5 record holds one row per release and the figures exist.
  h5::File f(h5, h5::File::Mode::kRead);
  EXPECT_EQ(f.read_strings("/calibration/releases/id").size(), doc["releases"].size());
  for (const char* svg :
       {"calibrate_parameters_cdf.svg", "calibrate_intervals.svg", "calibrate_fit.svg"})
    EXPECT_TRUE(fs::exists(dir_ / "fig" / svg)) << svg;
}

TEST_F(CmdCalibrate, ResumeSkipsDoneReleasesAndGivesTheSameAnswer) {
  const std::string h5 = (dir_ / "cal.h5").string();
  const std::string args = "calibrate " + quote(kLab + "cylinders.csv") +
                           " --where 'vin_x>=3.07' --no-intervals --json --out " + quote(h5);
  const RunResult first = ricochet(args);
  ASSERT_EQ(first.status, 0) << first.err;
  const RunResult again = ricochet(args + " --resume");
  ASSERT_EQ(again.status, 0) << again.err;
  const auto a = nlohmann::json::parse(first.out), b = nlohmann::json::parse(again.out);
  ASSERT_EQ(a["releases"].size(), 6u);  // C09, C13, C18, C19, C26, C28
  ASSERT_EQ(b["releases"].size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(a["releases"][i]["id"], b["releases"][i]["id"]);
    EXPECT_EQ(a["releases"][i]["params"], b["releases"][i]["params"]);
  }
  // Nothing was recomputed: the file still has one row per release.
  h5::File f(h5, h5::File::Mode::kRead);
  EXPECT_EQ(f.read_strings("/calibration/releases/id").size(), 6u);
  // Resuming with another seed is refused, naming the file.
  const RunResult other = ricochet(args + " --resume --seed 9");
  EXPECT_EQ(other.status, 2);
  EXPECT_NE(other.err.find(h5), std::string::npos) << other.err;
}

TEST_F(CmdCalibrate, TextOutputNeverPrintsAnUnidentifiedValueAlone) {
  const RunResult run =
      ricochet("calibrate " + quote(kLab + "cylinders.csv") + " --where 'vin_x>=3.07'");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("en2 = "), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("mu = "), std::string::npos) << run.out;  // mu is never identified here
  EXPECT_NE(run.out.find("not identified"), std::string::npos) << run.out;
}

TEST_F(CmdCalibrate, BadInputsExitWithTwoAndNameTheField) {
  RunResult run =
      ricochet("calibrate " + quote(kLab + "cylinders.csv") + " --shape triangle --json");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("shape"), std::string::npos) << run.err;
  EXPECT_TRUE(run.out.empty());
  run = ricochet("calibrate " + quote(kLab + "cylinders.csv") + " --sigma 0.1,0.1 --json");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("--sigma"), std::string::npos) << run.err;
  run = ricochet("calibrate " + quote(kLab + "cylinders.csv") + " --resume --json");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("--resume"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace ricochet
