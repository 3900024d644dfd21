// The resolved campaigns shipped under data/resolved/ (hours of LIGGGHTS, docs/resolved-model.md)
// are impact sets every tool reads: `ricochet stats FILE.h5 --json` succeeds on each of them and
// finds the releases its index says rebounded, with finite rebound velocities.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "support/program_test.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
using test::quote;

class ShippedData : public test::ProgramTest {};

TEST_F(ShippedData, StatsReadsEveryResolvedCampaign) {
  // The rebounds of each shipped campaign, as its run reported them (data/resolved/README.md and
  // the campaign logs; the others reached an end wall or a time limit). A truncated or
  // regenerated file changes its count, and a file not listed here fails until it is listed.
  const std::map<std::string, int> rebounds = {{"bed-calibration.h5", 102},
                                               {"bed-calibration-long.h5", 60},
                                               {"bed-calibration-refine.h5", 48},
                                               {"bed-calibration-cdt.h5", 80},
                                               {"bed-calibration-default.h5", 20},
                                               {"bed-calibration-rolling-gb.h5", 20},
                                               {"lab-cylinders-default-calibrated-ground.h5", 28},
                                               {"lab-cylinders-rolling-gb-ground.h5", 28},
                                               {"lab-triangles-blind-default-calibrated.h5", 26},
                                               {"lab-triangles-blind-rolling-gb.h5", 28},
                                               {"lab-triangles-fine-grains.h5", 6},
                                               {"lab-cylinders-default-replica-beds.h5", 28},
                                               {"lab-cylinders-packing-scatter.h5", 28},
                                               {"bed-probe-depth.h5", 6},
                                               {"bed-probe-rolling.h5", 8},
                                               {"bed-probe-rolling-model.h5", 6},
                                               {"bed-probe-resolution-cdt.h5", 8},
                                               {"bed-probe-width-cdt.h5", 4},
                                               {"bed-probe-block-cdt.h5", 6},
                                               {"bed-probe-default-ground.h5", 5},
                                               {"bed-probe-exit-slip.h5", 12},
                                               {"default-bed.h5", 2},
                                               {"bed-probe-stiffness.h5", 23},
                                               // partial: grows as the campaign resumes
                                               {"stiffness-plateau.h5", 63},
                                               {"convergence.h5", 27},
                                               {"lab-cylinders.h5", 28},
                                               {"lab-cylinders-long.h5", 28},
                                               {"lab-cylinders-cdt.h5", 84},
                                               {"lab-cylinders-cdt-ground.h5", 84},
                                               {"lab-cylinders-default-ground.h5", 28},
                                               {"lab-cylinders-default-tuned-ground.h5", 28},
                                               {"lab-triangles-blind-cdt.h5", 28},
                                               {"lab-cylinders-long-deep.h5", 28},
                                               {"lab-cylinders-long-replicas.h5", 84},
                                               {"lab-cylinders-replicas.h5", 67},
                                               {"lab-triangles-blind.h5", 26},
                                               {"lab-triangles-blind-long.h5", 30},
                                               {"speeds.h5", 17},
                                               {"speeds-cdt.h5", 19},
                                               {"speeds-rolling-gb.h5", 23},
                                               {"speeds-long.h5", 27}};
  const fs::path dir = fs::path(RICOCHET_SOURCE_DIR) / "data/resolved";
  std::set<std::string> seen;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".h5") continue;
    const std::string name = entry.path().filename().string();
    seen.insert(name);
    const test::RunResult r = ricochet("stats " + quote(entry.path().string()) + " --json");
    ASSERT_EQ(r.status, 0) << entry.path() << "\n" << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("n")) << r.out.substr(0, 400);
    ASSERT_TRUE(rebounds.count(name)) << name << " is shipped but not listed here";
    EXPECT_EQ(j["n"].get<int>(), rebounds.at(name)) << name;
    for (const char* c : {"vout_x", "vout_y", "wout"})
      EXPECT_TRUE(std::isfinite(j["columns"][c]["mean"].get<double>())) << name << " " << c;
  }
  for (const auto& [name, n] : rebounds) EXPECT_TRUE(seen.count(name)) << name << " is missing";
}

}  // namespace
}  // namespace ricochet
