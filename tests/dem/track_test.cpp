// The block track's columns without LIGGGHTS: the deck's text file (with and without its title
// line, before and after the torque column), the HDF5 track of a campaign file read by its
// `columns` attribute (a 12-column file written before the torque and overlap columns existed,
// and a new one), and append_result's round trip.
#include <gtest/gtest.h>
#include <unistd.h>

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

TEST(DemTrack, ColumnNamesKeepTheFirstTwelveAndAddTorqueAndOverlap) {
  const auto& n = Track::column_names();
  ASSERT_EQ(n.size(), 14u);
  EXPECT_EQ(n[0], "t[s]");
  EXPECT_EQ(n[11], "ke_grains[J]");
  EXPECT_EQ(n[12], "torque[N*m]");
  EXPECT_EQ(n[13], "overlap_d_max[-]");
  Track tr;
  for (const auto& name : n) EXPECT_NE(tr.column(name), nullptr) << name;
  EXPECT_EQ(tr.column("torque"), &tr.torque);
  EXPECT_EQ(tr.column("nonsense[m]"), nullptr);
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
  const Track a = Track::read((d / "new.track.txt").string());
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
  const Track b = Track::read((d / "old.track.txt").string());
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
  const Track c = Track::read((d / "bare.track.txt").string());
  ASSERT_EQ(c.size(), 1u);
  EXPECT_DOUBLE_EQ(c.w[0], -65.0);
  EXPECT_TRUE(std::isnan(c.torque[0]));
}

TEST(DemTrack, CampaignTracksAreReadByTheirColumnsAttribute) {
  const fs::path d = temp_dir("h5");
  const std::string path = (d / "old.h5").string();
  {
    // A campaign file of the first layout: 12 columns, named by the attribute.
    h5::File f(path, h5::File::Mode::kTruncate);
    const std::vector<double> rows = {0.001, 0.1,   0.2, 0, 2.9,   -2.3,  -65,   0,
                                      0,     -0.01, 10,  0, 0.002, 0.103, 0.198, -0.06,
                                      2.9,   -2.31, -65, 5, 40,    0.001, 9.5,   0.1};
    f.write("/dem/tracks/old", rows, {2, 12});
    f.set_attr("/dem/tracks/old", "columns",
               "t[s],x[m],y[m],theta[rad],vx[m/s],vy[m/s],w[rad/s],fcx[N],fcy[N],penetration[m],"
               "ke_block[J],ke_grains[J]");
  }
  const Track old = read_campaign_track(path, "old");
  ASSERT_EQ(old.size(), 2u);
  EXPECT_DOUBLE_EQ(old.fcy[1], 40.0);
  EXPECT_DOUBLE_EQ(old.penetration[1], 0.001);
  EXPECT_TRUE(std::isnan(old.torque[1]));
  EXPECT_TRUE(std::isnan(old.overlap_d_max[1]));
  EXPECT_THROW(read_campaign_track(path, "missing"), std::runtime_error);

  // The current layout, written by append_result and read back column by column.
  ImpactResult r;
  r.id = "new";
  r.status = "timeout";
  for (int i = 0; i < 3; ++i)
    for (const auto& name : Track::column_names())
      r.track.column(name)->push_back(0.001 * (i + 1) + (name == "torque[N*m]" ? 7.0 : 0.0));
  ImpactSpec spec;
  spec.id = "new";
  const std::string path2 = (d / "new.h5").string();
  append_result(path2, r, spec, "test");
  const Track back = read_campaign_track(path2, "new");
  ASSERT_EQ(back.size(), 3u);
  EXPECT_DOUBLE_EQ(back.torque[2], 7.003);
  EXPECT_DOUBLE_EQ(back.overlap_d_max[1], 0.002);
  h5::File f(path2, h5::File::Mode::kRead);
  std::vector<std::size_t> dims;
  f.read_doubles("/dem/tracks/new", &dims);
  ASSERT_EQ(dims.size(), 2u);
  EXPECT_EQ(dims[1], Track::column_names().size());
}

TEST(DemTrack, FromRowsRejectsRaggedDataAndATrackWithoutTime) {
  EXPECT_THROW(Track::from_rows({1, 2, 3}, {"t[s]", "x[m]"}), std::invalid_argument);
  EXPECT_THROW(Track::from_rows({1, 2}, {"x[m]", "y[m]"}), std::invalid_argument);
  const Track t = Track::from_rows({1, 2, 3, 4}, {"x[m]", "t[s]", "unknown[-]", "w[rad/s]"});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_DOUBLE_EQ(t.t[0], 2.0);
  EXPECT_DOUBLE_EQ(t.w[0], 4.0);
  EXPECT_TRUE(std::isnan(t.vx[0]));
}

}  // namespace
