// The block track without LIGGGHTS: the deck's text file (with and without its title line, before
// and after the torque column), append_result's round trip through the library's writer and
// reader (impact/block_track.hpp; tests/impact/block_track_test.cpp covers the reader's rules),
// with the slab block's mass on the track and in the index, and a campaign index written before
// block_mass_kg existed, widened when a resumed campaign appends to it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "campaign.hpp"
#include "common/h5.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::dem;
namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("dem-track-test-" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(DemTrack, TextFileIsReadByItsTitleLine) {
  const fs::path d = temp_dir("text");
  {
    // The deck's layout now: twelve columns, then the torque; a line cut by a crash at the end.
    std::ofstream f(d / "new.track.txt");
    f << "# t[s] x[m] y[m] theta[rad] vx[m/s] vy[m/s] w[rad/s] fcx[N] fcy[N] penetration[m] "
         "ke_block[J] ke_grains[J] torque[N*m]\n";
    f << "0.001 0.1 0.2 0.0 2.9 -2.3 -65 0 0 -0.01 10 0 0\n";
    f << "0.002 0.103 0.198 -0.065 2.9 -2.31 -65 5 40 0.001 9.5 0.1 1.25\n";
    f << "0.003 0.106 0.196 6.1 2.9 -2.32 -64";  // cut
  }
  const BlockTrack a = read_deck_track((d / "new.track.txt").string());
  ASSERT_EQ(a.size(), 2u);
  EXPECT_DOUBLE_EQ(a.torque[1], 1.25);
  EXPECT_DOUBLE_EQ(a.fcy[1], 40.0);
  ASSERT_EQ(a.overlap_d_max.size(), 2u);  // not in the deck's file: NaN
  EXPECT_TRUE(std::isnan(a.overlap_d_max[0]));
  {
    // A track from before the torque: its title names twelve columns.
    std::ofstream f(d / "old.track.txt");
    f << "# t[s] x[m] y[m] theta[rad] vx[m/s] vy[m/s] w[rad/s] fcx[N] fcy[N] penetration[m] "
         "ke_block[J] ke_grains[J]\n";
    f << "0.001 0.1 0.2 3.0 2.9 -2.3 -65 0 0 -0.01 10 0\n";
    f << "0.002 0.103 0.198 -3.0 2.9 -2.31 -65 5 40 0.001 9.5 0.1\n";
  }
  const BlockTrack b = read_deck_track((d / "old.track.txt").string());
  ASSERT_EQ(b.size(), 2u);
  EXPECT_DOUBLE_EQ(b.ke_grains[1], 0.1);
  EXPECT_TRUE(std::isnan(b.torque[0]));
  EXPECT_TRUE(std::isnan(b.torque[1]));
  // theta is unwrapped: 3.0 -> -3.0 is a small step forward across pi.
  EXPECT_NEAR(b.theta[1], 2 * std::numbers::pi - 3.0, 1e-12);
  {
    // No title line at all: twelve legacy columns.
    std::ofstream f(d / "bare.track.txt");
    f << "0.001 0.1 0.2 0 2.9 -2.3 -65 0 0 -0.01 10 0\n";
  }
  const BlockTrack c = read_deck_track((d / "bare.track.txt").string());
  ASSERT_EQ(c.size(), 1u);
  EXPECT_DOUBLE_EQ(c.w[0], -65.0);
  EXPECT_TRUE(std::isnan(c.torque[0]));
}

TEST(DemTrack, AppendResultKeepsTheTrackAndTheBlockMass) {
  const fs::path d = temp_dir("h5");
  ImpactResult r;
  r.id = "new";
  r.status = "timeout";
  r.block_mass_kg = 9.586;
  for (int i = 0; i < 3; ++i)
    for (const auto& name : BlockTrack::column_names())
      r.track.column(name)->push_back(0.001 * (i + 1) + (name == "torque[N*m]" ? 7.0 : 0.0));
  r.track.block_mass_kg = r.block_mass_kg;
  ImpactSpec spec;
  spec.id = "new";
  const std::string path = (d / "new.h5").string();
  append_result(path, r, spec, "test");
  const BlockTrack back = read_campaign_track(path, "new");
  ASSERT_EQ(back.size(), 3u);
  EXPECT_DOUBLE_EQ(back.torque[2], 7.003);
  EXPECT_DOUBLE_EQ(back.overlap_d_max[1], 0.002);
  EXPECT_DOUBLE_EQ(back.block_mass_kg, 9.586);
  EXPECT_THROW(read_campaign_track(path, "missing"), std::runtime_error);
  const auto index = read_campaign_index(path);
  ASSERT_EQ(index.size(), 1u);
  const auto& names = campaign_value_names();
  const auto k = static_cast<std::size_t>(std::find(names.begin(), names.end(), "block_mass_kg") -
                                          names.begin());
  ASSERT_LT(k, names.size());
  EXPECT_DOUBLE_EQ(index[0].values[k], 9.586);
}

TEST(DemTrack, AnIndexFromBeforeTheBlockMassIsWidenedOnAppend) {
  const fs::path d = temp_dir("widen");
  const std::string path = (d / "old.h5").string();
  const auto& names = campaign_value_names();
  ASSERT_EQ(names.back(), "block_mass_kg");
  const std::size_t old_width = names.size() - 1;  // everything but block_mass_kg
  {
    h5::File f(path, h5::File::Mode::kTruncate);
    const std::vector<double> row(old_width, 1.5);
    f.append_rows("/dem/index/values", row, old_width);
    for (const char* c : {"id", "status", "message", "shape", "bed_key", "work_dir", "params"})
      f.append_strings(std::string("/dem/index/") + c, {std::string(c) == "id" ? "old" : ""});
  }
  const auto before = read_campaign_index(path);
  ASSERT_EQ(before.size(), 1u);
  ASSERT_EQ(before[0].values.size(), names.size());
  EXPECT_TRUE(std::isnan(before[0].values.back()));

  ImpactResult r;
  r.id = "new";
  r.status = "timeout";
  r.block_mass_kg = 2.0;
  ImpactSpec spec;
  spec.id = "new";
  append_result(path, r, spec, "test");
  const auto after = read_campaign_index(path);
  ASSERT_EQ(after.size(), 2u);
  EXPECT_EQ(after[0].id, "old");
  EXPECT_DOUBLE_EQ(after[0].values[0], 1.5);
  EXPECT_TRUE(std::isnan(after[0].values.back()));
  EXPECT_DOUBLE_EQ(after[1].values.back(), 2.0);
}

}  // namespace
