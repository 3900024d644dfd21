// HDF5 records of calibrations: incremental rows, round trip, resume of a killed run, refusal to
// resume with other settings. Real files in a temporary directory.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "fit/fit_io.hpp"

namespace ricochet::fit {
namespace {

namespace fs = std::filesystem;
const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

class FitIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ricochet-fit-io-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    set_ = read_impact_set(kLab + "cylinders.csv");
    set_.impacts.resize(3);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  ImpactSet set_;
};

TEST_F(FitIo, RoundTripAndResume) {
  const Model model = Model::paper();
  const Shape shape = Shape::cylinder();
  FitOptions o;
  const std::string path = (dir_ / "cal.h5").string();
  const auto fits = calibrate_releases(model, shape, set_, o);
  {
    // A run killed after two releases.
    ReleaseFitStore store(path, model, shape, set_, o, false);
    store.append(0, fits[0]);
    store.append(1, fits[1]);
  }
  ReleaseFitStore resumed(path, model, shape, set_, o, true);
  EXPECT_TRUE(resumed.done("C01"));
  EXPECT_TRUE(resumed.done("C02"));
  EXPECT_FALSE(resumed.done("C03"));
  ASSERT_EQ(resumed.existing().size(), 2u);
  const ReleaseFit& back = resumed.existing()[1];
  EXPECT_EQ(back.id, "C02");
  EXPECT_EQ(back.params, fits[1].params);
  EXPECT_EQ(back.error, fits[1].error);
  EXPECT_EQ(back.simulated, fits[1].simulated);
  ASSERT_EQ(back.intervals.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(back.intervals[k].lo, fits[1].intervals[k].lo);
    EXPECT_EQ(back.intervals[k].hi, fits[1].intervals[k].hi);
    EXPECT_EQ(back.intervals[k].status, fits[1].intervals[k].status);
    EXPECT_EQ(back.intervals[k].statement, fits[1].intervals[k].statement);
  }
  resumed.append(2, fits[2]);
  resumed.write_summary(fits, nullptr, 1.0);
  const auto all = read_release_fits(path);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[2].id, "C03");
  h5::File f(path, h5::File::Mode::kRead);
  EXPECT_EQ(f.attr_string("/calibration", "schema"), "ricochet-calibration-1");
  EXPECT_EQ(f.attr_double("/calibration", "seed"), 1.0);
  EXPECT_TRUE(f.exists("/calibration/impacts"));
  EXPECT_TRUE(f.exists("/calibration/profiles/C01/mu"));
  EXPECT_NE(f.attr_string("/calibration", "model_toml").find("normal"), std::string::npos);
  const auto summary = nlohmann::json::parse(f.attr_string("/calibration/summary", "json"));
  EXPECT_TRUE(summary.contains("en2"));
}

TEST_F(FitIo, RefusesToResumeWithOtherSettings) {
  const Model model = Model::paper();
  const Shape shape = Shape::cylinder();
  FitOptions o;
  const std::string path = (dir_ / "cal.h5").string();
  { ReleaseFitStore store(path, model, shape, set_, o, false); }
  o.seed = 2;
  try {
    ReleaseFitStore again(path, model, shape, set_, o, true);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(e.field().find("settings_json"), std::string::npos) << e.what();
  }
}

TEST_F(FitIo, JsonSummaryCountsIdentifiability) {
  FitOptions o;
  const auto fits = calibrate_releases(Model::paper(), Shape::cylinder(), set_, o);
  const nlohmann::json s = summary_json(fits);
  int total = 0;
  for (const auto& [k, v] : s["mu"]["counts"].items()) total += v.get<int>();
  EXPECT_EQ(total, 3);
  EXPECT_EQ(s["en2"]["n"], 3);
  const nlohmann::json r = to_json(fits[0]);
  for (const char* key : {"id", "params", "intervals", "error", "identifiability", "statements"})
    EXPECT_TRUE(r.contains(key)) << key;
  EXPECT_EQ(r["intervals"]["en2"].size(), 2u);
  EXPECT_FALSE(r["params"].contains("kn"));  // fixed parameters are listed apart
  EXPECT_TRUE(r["fixed"].contains("kn"));
}

}  // namespace
}  // namespace ricochet::fit
