// The resolved campaigns shipped under data/resolved/ (hours of LIGGGHTS, docs/resolved-model.md)
// are impact sets every tool reads: `ricochet stats FILE.h5 --json` succeeds on each of them and
// finds the releases its index says rebounded, with finite rebound velocities.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "support/program_test.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
using test::quote;

class ShippedData : public test::ProgramTest {};

TEST_F(ShippedData, StatsReadsEveryResolvedCampaign) {
  const fs::path dir = fs::path(RICOCHET_SOURCE_DIR) / "data/resolved";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".h5") continue;
    ++files;
    const test::RunResult r = ricochet("stats " + quote(entry.path().string()) + " --json");
    ASSERT_EQ(r.status, 0) << entry.path() << "\n" << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("n")) << r.out.substr(0, 400);
    // The fewest rebounds of a shipped campaign: speeds.h5, 17 of 27 (the others reached an
    // end wall of the small slab; data/resolved/README.md).
    EXPECT_GE(j["n"].get<int>(), 17) << entry.path();
    for (const char* c : {"vout_x", "vout_y", "wout"})
      EXPECT_TRUE(std::isfinite(j["columns"][c]["mean"].get<double>())) << entry.path() << " " << c;
  }
  // bed-calibration, bed-calibration-long, bed-calibration-refine, bed-probe-rolling,
  // bed-probe-stiffness, convergence, lab-cylinders, lab-cylinders-long,
  // lab-cylinders-long-replicas, lab-cylinders-replicas, lab-triangles-blind,
  // lab-triangles-blind-long, speeds, speeds-long
  EXPECT_GE(files, 14);
}

}  // namespace
}  // namespace ricochet
