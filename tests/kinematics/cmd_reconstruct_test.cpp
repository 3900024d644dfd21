// Runs the built `ricochet reconstruct` program on a synthetic video track written to disk: the
// JSON keys, the impact-set output (readable by every tool), the figure and the errors.
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

#include "impact/impact_set.hpp"
#include "support/program_test.hpp"
#include "synthetic_track.hpp"

namespace ricochet {
namespace {

using test::quote;
using test::slurp;
using Result = test::RunResult;

namespace fs = std::filesystem;
using nlohmann::json;

class CmdReconstruct : public test::ProgramTest {
 protected:
  void SetUp() override {
    ProgramTest::SetUp();
    track_ = (dir_ / "release 01.csv").string();  // a space in the name on purpose
    std::ofstream(track_) << impact_.csv(400, 0.14, 1e-3, 0.7, 5);
  }
  std::string track_;
  test::SyntheticImpact impact_;
};

TEST_F(CmdReconstruct, JsonWithTheTrueWindowRecoversTheVelocities) {
  const Result r = ricochet("reconstruct " + quote(track_) +
                            " --pixel-size 0.001 --window 0.0513,0.0813 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json doc = json::parse(r.out);
  EXPECT_EQ(doc["window"]["method"], "given");
  EXPECT_FALSE(doc["window"]["detected"].get<bool>());
  for (int c = 0; c < 3; ++c) {
    const char* k = kComponentNames[c];
    EXPECT_NEAR(doc["vin"][k].get<double>(), impact_.vin[c], 4 * doc["sigma_vin"][k].get<double>());
    EXPECT_NEAR(doc["vout"][k].get<double>(), impact_.vout[c],
                4 * doc["sigma_vout"][k].get<double>());
  }
  EXPECT_EQ(doc["noise"]["source"], "residuals");
  EXPECT_TRUE(doc["gravity"]["imposed"].get<bool>());
}

TEST_F(CmdReconstruct, DetectedWindowOutputAsAnImpactSetAndAFigure) {
  const std::string out = (dir_ / "impact.csv").string();
  const Result r = ricochet("reconstruct " + quote(track_) +
                            " --pixel-size 0.001 --id R01 --shape cylinder --out " + quote(out) +
                            " --figures " + quote(dir_.string()) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json doc = json::parse(r.out);
  EXPECT_TRUE(doc["window"]["detected"].get<bool>());
  EXPECT_NEAR(doc["window"]["start_s"].get<double>(), impact_.t0, 3 * 0.0025);
  EXPECT_NEAR(doc["window"]["end_s"].get<double>(), impact_.t1, 3 * 0.0025);
  // The output is one release in the impact-set schema, with the standard errors.
  const ImpactSet set = read_impact_set(out);
  ASSERT_EQ(set.size(), 1u);
  EXPECT_EQ(set.impacts[0].id, "R01");
  EXPECT_EQ(set.impacts[0].shape, "cylinder");
  EXPECT_DOUBLE_EQ(set.impacts[0].vin[kVx], doc["vin"]["vx"].get<double>());
  ASSERT_TRUE(set.impacts[0].sigma_vout.has_value());
  EXPECT_DOUBLE_EQ((*set.impacts[0].sigma_vout)[kW], doc["sigma_vout"]["w"].get<double>());
  ASSERT_TRUE(set.impacts[0].contact_duration.has_value());
  EXPECT_NEAR(*set.impacts[0].contact_duration, doc["window"]["duration_s"].get<double>(), 1e-12);
  ASSERT_EQ(doc["figures"].size(), 1u);
  const std::string svg = slurp(doc["figures"][0].get<std::string>());
  EXPECT_NE(svg.find("<svg"), std::string::npos);
}

TEST_F(CmdReconstruct, ErrorsExitWithStatus2AndNameTheCulprit) {
  Result r = ricochet("reconstruct " + quote(track_));  // px without --pixel-size
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("release 01.csv:2: field 'x'"), std::string::npos) << r.err;
  r = ricochet("reconstruct " + quote(track_) + " --pixel-size 0.001 --window 0.08,0.05");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--window"), std::string::npos) << r.err;
  r = ricochet("reconstruct " + quote(track_) + " --pixel-size 0.001 --ground 0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--radius"), std::string::npos) << r.err;
  r = ricochet("reconstruct " + quote(track_) + " --pixel-size 0.001 --window 0.0,0.139");
  EXPECT_EQ(r.status, 2);  // no free flight left on either side
  EXPECT_NE(r.err.find("fewer than 3 points"), std::string::npos) << r.err;
  r = ricochet("reconstruct " + quote(track_) +
               " --pixel-size 0.001 --gravity 9.81 --free-gravity");
  EXPECT_NE(r.status, 0);
}

}  // namespace
}  // namespace ricochet
