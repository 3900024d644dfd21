// `ricochet stats` answers every file shipped under data/ (issue 32: "ricochet stats works on
// every shipped file"). The impact data (the lab's sets, the plans of throws, and the resolved
// campaigns, hours of LIGGGHTS, docs/resolved-model.md) are read: each campaign's releases are
// those its index says rebounded, with finite rebound velocities, and the campaigns that keep
// tracks get their contact numbers. Every other file (documentation, JSON results, the
// detection study's tables, the sphere-drop tables, shape files) is refused as bad input, status
// 2, with a message that names it: one of each kind (folder and extension) is run.
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

TEST_F(ShippedData, StatsAnswersEveryShippedFile) {
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
                                               {"stiffness-plateau.h5", 67},
                                               {"wall-stiffness.h5", 3},
                                               // partial: grows as the campaign resumes
                                               {"wall-stiffness-1.5e10.h5", 3},
                                               {"sand-calibration-1.5e9.h5", 28},
                                               {"sand-zone-check-1.5e9.h5", 8},
                                               {"sand-verification-1.5e9.h5", 27},
                                               {"sand-blind-triangles-1.5e9.h5", 30},
                                               {"timestep-1.5e9.h5", 4},
                                               {"convergence.h5", 27},
                                               // partial: grows as the campaign resumes
                                               {"convergence-1.5e9.h5", 5},
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
  // The campaigns that keep tracks (/dem/tracks): releases with a track, and tracks of impacts
  // that did not rebound. The others were shipped with /impacts and /dem/index only.
  const std::map<std::string, std::pair<int, int>> tracks = {
      {"lab-cylinders.h5", {28, 0}},
      {"lab-cylinders-long.h5", {28, 0}},
      {"lab-cylinders-long-deep.h5", {28, 0}},
      {"lab-triangles-blind.h5", {26, 5}},
      {"lab-triangles-blind-long.h5", {30, 1}},
      {"stiffness-plateau.h5", {67, 0}},
      {"wall-stiffness.h5", {3, 0}},
      {"wall-stiffness-1.5e10.h5", {3, 0}},
      {"sand-calibration-1.5e9.h5", {28, 26}},
      {"sand-zone-check-1.5e9.h5", {8, 0}},
      {"sand-verification-1.5e9.h5", {27, 1}},
      {"sand-blind-triangles-1.5e9.h5", {30, 7}},
      {"convergence-1.5e9.h5", {5, 2}},
      {"timestep-1.5e9.h5", {4, 0}}};
  const fs::path data = fs::path(RICOCHET_SOURCE_DIR) / "data";
  std::set<std::string> seen, other_kinds;
  int impact_files = 0, other_files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(data)) {
    if (!entry.is_regular_file()) continue;
    const fs::path& path = entry.path();
    const std::string name = path.filename().string();
    const std::string folder = path.parent_path().filename().string();
    const bool impact_data = path.extension() == ".h5" || (path.extension() == ".csv" &&
                                                           (folder == "lab" || folder == "design"));
    if (!impact_data) {
      // Refused by its extension before it is read, or a CSV by its header: one file of each
      // folder and extension stands for the others (a run of the program costs 0.1-0.2 s, and
      // there are 70 such files).
      if (!other_kinds.insert(folder + "/" + path.extension().string()).second) continue;
      ++other_files;
      const test::RunResult r = ricochet("stats " + quote(path.string()) + " --json");
      EXPECT_EQ(r.status, 2) << path << "\n" << r.out;
      EXPECT_TRUE(r.out.empty()) << path << "\n" << r.out.substr(0, 400);
      EXPECT_NE(r.err.find(path.string()), std::string::npos) << r.err;
      continue;
    }
    ++impact_files;
    const test::RunResult r = ricochet("stats " + quote(path.string()) + " --json");
    ASSERT_EQ(r.status, 0) << path << "\n" << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("n")) << r.out.substr(0, 400);
    EXPECT_GT(j["n"].get<int>(), 0) << name;
    if (folder == "design") {
      // A plan of throws: its incident states summarised, no reflected velocity.
      EXPECT_TRUE(j["incident_only"].get<bool>()) << name;
      EXPECT_TRUE(std::isfinite(j["columns"]["vin_y"]["mean"].get<double>())) << name;
      EXPECT_TRUE(j["columns"]["vout_y"]["mean"].is_null()) << name;
    }
    if (folder != "resolved") continue;
    seen.insert(name);
    ASSERT_TRUE(rebounds.count(name)) << name << " is shipped but not listed here";
    EXPECT_EQ(j["n"].get<int>(), rebounds.at(name)) << name;
    for (const char* c : {"vout_x", "vout_y", "wout"})
      EXPECT_TRUE(std::isfinite(j["columns"][c]["mean"].get<double>())) << name << " " << c;
    // A campaign file's outcomes (its /dem/index): every rebound of the index is a release of
    // the set, the statuses add up, and the captured share lies in its interval.
    if (const auto& oc = j["outcomes"]; !oc.is_null()) {
      const auto& by = oc["by_status"];
      EXPECT_EQ(by.value("rebound", 0), j["n"].get<int>()) << name;
      int sum = 0, failures = 0;
      for (const auto& [status, count] : by.items()) {
        sum += count.get<int>();
        if (status == "invalid" || status == "lost_atoms" || status == "extraction_failed" ||
            status == "crashed")
          failures += count.get<int>();
      }
      EXPECT_EQ(sum, oc["impacts"].get<int>()) << name;
      EXPECT_EQ(oc["ran"].get<int>(), sum - failures) << name;
      EXPECT_EQ(oc["captured"].get<int>(), by.value("timeout", 0) + by.value("no_rebound", 0))
          << name;
      EXPECT_LE(oc["capture"]["lo"].get<double>(), oc["capture"]["rate"].get<double>()) << name;
      EXPECT_GE(oc["capture"]["hi"].get<double>(), oc["capture"]["rate"].get<double>()) << name;
      // Where a captured impact's track ends: only captures, at most one each, at a time.
      EXPECT_LE(oc["captured_ends"].size(), oc["captured"].get<std::size_t>()) << name;
      for (const auto& e : oc["captured_ends"]) {
        const std::string status = e["status"].get<std::string>();
        EXPECT_TRUE(status == "timeout" || status == "no_rebound") << name << " " << e["id"];
        EXPECT_GT(e["t"].get<double>(), 0) << name << " " << e["id"];
      }
    }
    const auto& t = j["tracks"];
    if (!tracks.count(name)) {
      EXPECT_TRUE(t.is_null()) << name << " keeps tracks: list it above";
      continue;
    }
    ASSERT_TRUE(t.is_object()) << name << ": no track summary";
    EXPECT_EQ(t["with_track"].get<int>(), tracks.at(name).first) << name;
    EXPECT_EQ(t["other_tracks"].get<int>(), tracks.at(name).second) << name;
    for (const auto& c : t["impacts"]) {
      // Every track has a contact: a window longer than a millisecond and within the track (the
      // sand calibration's design points roll on the bed for up to 0.24 s above 0.2 x the block's
      // weight before they leave it), a positive peak force, records at most 0.5 ms apart
      // (issue 32, item 4), and the slab block's mass.
      const std::string id = c["id"].get<std::string>();
      ASSERT_TRUE(c["contact_duration"].is_number()) << name << " " << id;
      EXPECT_GT(c["contact_duration"].get<double>(), 1e-3) << name << " " << id;
      EXPECT_LE(c["contact_duration"].get<double>(),
                c["records"].get<double>() * c["max_interval"].get<double>())
          << name << " " << id;
      EXPECT_GT(c["peak_normal_force"].get<double>(), 0) << name << " " << id;
      EXPECT_LE(c["max_interval"].get<double>(), 5e-4) << name << " " << id;
      EXPECT_GT(c["block_mass"].get<double>(), 0) << name << " " << id;
    }
  }
  for (const auto& [name, n] : rebounds) EXPECT_TRUE(seen.count(name)) << name << " is missing";
  // The campaigns, the lab's two sets and the plan of throws in data/design.
  EXPECT_EQ(impact_files, static_cast<int>(rebounds.size()) + 3);
  EXPECT_GT(other_files, 0);
}

}  // namespace
}  // namespace ricochet
