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

#include "impact/block_track.hpp"
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

TEST_F(CmdReconstruct, TrackForcesWriteTheContactForceBesideTheRelease) {
  const std::string out = (dir_ / "video.h5").string();
  const Result r = ricochet("reconstruct " + quote(track_) +
                            " --pixel-size 0.001 --id R01 --shape cylinder --track-forces --out " +
                            quote(out) + " --figures " + quote(dir_.string()) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json doc = json::parse(r.out);
  ASSERT_TRUE(doc.contains("track_forces"));
  EXPECT_EQ(doc["track_forces"]["track"], "/dem/tracks/R01");
  EXPECT_NEAR(doc["track_forces"]["span_s"].get<double>(), 4 * 0.0025, 1e-9);  // 5 frames
  const double ratio = 0.01 / doc["window"]["duration_s"].get<double>();
  EXPECT_NEAR(doc["track_forces"]["span_over_contact"].get<double>(), ratio, 1e-9);
  EXPECT_EQ(doc["track_forces"]["blurred"].get<bool>(), ratio > 1.0 / 3.0);
  ASSERT_EQ(doc["figures"].size(), 2u);
  EXPECT_NE(slurp(doc["figures"][1].get<std::string>()).find("fcy"), std::string::npos);
  // The file is an impact set with its track, as a LIGGGHTS campaign's: every reader takes it.
  EXPECT_EQ(read_impact_set(out).size(), 1u);
  ASSERT_EQ(block_track_ids(out), std::vector<std::string>{"R01"});
  const BlockTrack b = read_block_track(out, "R01");
  EXPECT_DOUBLE_EQ(b.block_mass_kg, 13.9);  // the catalog cylinder (paper Fig. 4)
  // The half-sine contact of the synthetic impact peaks at m (dV_y + g T) pi / (2 T), 2.5 kN;
  // a 10 ms fit flattens it by at most 20 %, and the 1 px pointing noise adds the stated s.e.
  const double T = impact_.t1 - impact_.t0;
  const double peak = 13.9 * (impact_.vout[1] - impact_.vin[1] + impact_.g * T) * M_PI / (2 * T);
  const double got = doc["track_forces"]["peak_fcy_N"].get<double>();
  const double se = doc["track_forces"]["sigma_at_peak_N"].get<double>();
  EXPECT_GT(se, 0.0);
  EXPECT_GT(got, 0.8 * peak - 3 * se);
  EXPECT_LT(got, peak + 3 * se);
  for (std::size_t i = 0; i < b.size(); ++i) {
    EXPECT_TRUE(std::isfinite(b.sigma_fcy[i]) && std::isfinite(b.sigma_torque[i]));
    EXPECT_TRUE(std::isfinite(b.penetration[i]));  // y is measured from the surface y = 0
  }
}

TEST_F(CmdReconstruct, SeveralTracksMakeOneSetWithTheirTracks) {
  const std::string second = (dir_ / "R02.csv").string();
  std::ofstream(second) << impact_.csv(400, 0.14, 1e-3, 0.7, 6);  // another noise draw
  const std::string out = (dir_ / "series.h5").string();
  Result r = ricochet("reconstruct " + quote(track_) + " " + quote(second) +
                      " --pixel-size 0.001 --shape cylinder --track-forces --out " + quote(out) +
                      " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json doc = json::parse(r.out);
  ASSERT_EQ(doc["releases"].size(), 2u);
  EXPECT_EQ(doc["releases"][1]["id"], "R02");
  const ImpactSet set = read_impact_set(out);
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.impacts[0].id, "release 01");  // the file names without their extension
  EXPECT_EQ(block_track_ids(out).size(), 2u);
  // The same name in two folders is the same id: refused, naming both files.
  fs::create_directory(dir_ / "other");
  const std::string twin = (dir_ / "other" / "R02.csv").string();
  fs::copy_file(second, twin);
  r = ricochet("reconstruct " + quote(second) + " " + quote(twin) + " --pixel-size 0.001");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("also the id of"), std::string::npos) << r.err;
  r = ricochet("reconstruct " + quote(track_) + " " + quote(second) + " --pixel-size 0.001 --id X");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--id"), std::string::npos) << r.err;
}

TEST_F(CmdReconstruct, TrackForcesErrorsNameTheOption) {
  Result r = ricochet("reconstruct " + quote(track_) + " --pixel-size 0.001 --track-forces");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--track-forces"), std::string::npos) << r.err;
  const std::string csv = quote((dir_ / "one.csv").string());
  r = ricochet("reconstruct " + quote(track_) + " --pixel-size 0.001 --track-forces --shape " +
               "cylinder --out " + csv);
  EXPECT_EQ(r.status, 2);  // a CSV set cannot hold a track
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
  const std::string h5 = quote((dir_ / "one.h5").string());
  r = ricochet("reconstruct " + quote(track_) + " --pixel-size 0.001 --track-forces --out " + h5);
  EXPECT_EQ(r.status, 2);  // which block?
  EXPECT_NE(r.err.find("--shape"), std::string::npos) << r.err;
  r = ricochet("reconstruct " + quote(track_) +
               " --pixel-size 0.001 --track-forces --shape boulder --out " + h5);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("cylinder, triangle"), std::string::npos) << r.err;
  r = ricochet("reconstruct " + quote(track_) + " --pixel-size 0.001 --mass 5");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--mass"), std::string::npos) << r.err;
  r = ricochet("reconstruct " + quote(track_) +
               " --pixel-size 0.001 --track-forces --mass 5 --inertia 0.01 --smooth 0 --out " + h5);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("--smooth"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ricochet
