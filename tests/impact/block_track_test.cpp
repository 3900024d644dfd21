// The tracks of the impact-set schema (impact/block_track.hpp, docs/impact-sets.md "Tracks"):
// the writer and the library's reader round trip every column and the block mass; tracks written
// before the torque and overlap columns read them as NaN; a malformed track is an InputError
// naming the file and the track; the shipped campaigns' tracks read as their columns say.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "impact/block_track.hpp"
#include "support/temp_dir_test.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
const std::string kResolved = std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/";

class BlockTrackFile : public test::TempDirTest {
 protected:
  BlockTrackFile() : TempDirTest("ricochet-track") {}
};

// The InputError of `read`, or a failure when it does not throw one.
template <class F>
InputError error_of(F read) {
  try {
    read();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("", 0, "", "");
}

// The first campaigns' twelve columns, as their files name them.
const char* kLegacyColumns =
    "t[s],x[m],y[m],theta[rad],vx[m/s],vy[m/s],w[rad/s],fcx[N],fcy[N],penetration[m],"
    "ke_block[J],ke_grains[J]";

TEST(BlockTrack, SeventeenColumnsWithTheirSiUnits) {
  const auto& n = BlockTrack::column_names();
  ASSERT_EQ(n.size(), 17u);
  EXPECT_EQ(n[0], "t[s]");
  EXPECT_EQ(n[7], "fcx[N]");
  EXPECT_EQ(n[11], "ke_grains[J]");
  EXPECT_EQ(n[12], "torque[N*m]");
  EXPECT_EQ(n[13], "overlap_d_max[-]");
  EXPECT_EQ(n[14], "sigma_fcx[N]");  // standard errors of an estimated force (from video)
  EXPECT_EQ(n[16], "sigma_torque[N*m]");
  BlockTrack tr;
  for (const auto& name : n) EXPECT_NE(tr.column(name), nullptr) << name;
  EXPECT_EQ(tr.column("torque"), &tr.torque);
  EXPECT_EQ(tr.column(" penetration [m]"), &tr.penetration);
  EXPECT_EQ(tr.column("nonsense[m]"), nullptr);
}

TEST(BlockTrack, FromRowsTakesAnySubsetInAnyOrder) {
  EXPECT_THROW(BlockTrack::from_rows({1, 2, 3}, {"t[s]", "x[m]"}), std::invalid_argument);
  EXPECT_THROW(BlockTrack::from_rows({1, 2}, {"x[m]", "y[m]"}), std::invalid_argument);
  const BlockTrack t =
      BlockTrack::from_rows({1, 2, 3, 4}, {"x[m]", "t[s]", "unknown[-]", "w[rad/s]"});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_DOUBLE_EQ(t.t[0], 2.0);
  EXPECT_DOUBLE_EQ(t.x[0], 1.0);
  EXPECT_DOUBLE_EQ(t.w[0], 4.0);
  ASSERT_EQ(t.vx.size(), 1u);
  EXPECT_TRUE(std::isnan(t.vx[0]));
}

TEST_F(BlockTrackFile, RoundTripsEveryColumnAndTheBlockMass) {
  BlockTrack tr;
  const auto& names = BlockTrack::column_names();
  for (int i = 0; i < 5; ++i)
    for (std::size_t c = 0; c < names.size(); ++c)
      tr.column(names[c])->push_back(1e-3 * i + 0.1 * static_cast<double>(c) + 1.0 / 3.0);
  tr.block_mass_kg = 9.586;
  const std::string file = path("campaign.h5");
  write_block_track(file, "C01", tr);
  write_block_track(file, "C02", tr);
  const BlockTrack back = read_block_track(file, "C01");
  ASSERT_EQ(back.size(), 5u);
  for (const auto& name : names)
    for (std::size_t i = 0; i < 5; ++i)
      EXPECT_EQ((*back.column(name))[i], (*tr.column(name))[i]) << name << " " << i;  // bits
  EXPECT_EQ(back.block_mass_kg, 9.586);
  EXPECT_EQ(block_track_ids(file), (std::vector<std::string>{"C01", "C02"}));

  // Written again (a resumed impact): replaced, not appended.
  for (const auto& name : names) tr.column(name)->resize(3);
  tr.block_mass_kg = std::nan("");
  write_block_track(file, "C01", tr);
  const BlockTrack again = read_block_track(file, "C01");
  EXPECT_EQ(again.size(), 3u);
  EXPECT_TRUE(std::isnan(again.block_mass_kg));  // not written when unknown

  EXPECT_THROW(write_block_track(file, "", tr), std::invalid_argument);
  EXPECT_THROW(write_block_track(file, "empty", BlockTrack{}), std::invalid_argument);
}

TEST_F(BlockTrackFile, LegacyTracksReadTheirMissingColumnsAsNaN) {
  const std::string file = path("old.h5");
  const std::vector<double> rows = {0.001, 0.1,   0.2, 0, 2.9,   -2.3,  -65,   0,
                                    0,     -0.01, 10,  0, 0.002, 0.103, 0.198, -0.06,
                                    2.9,   -2.31, -65, 5, 40,    0.001, 9.5,   0.1};
  {
    h5::File f(file, h5::File::Mode::kTruncate);
    f.write("/dem/tracks/named", rows, {2, 12});
    f.set_attr("/dem/tracks/named", "columns", kLegacyColumns);
    f.write("/dem/tracks/bare", rows, {2, 12});  // before the attribute existed
  }
  for (const char* id : {"named", "bare"}) {
    const BlockTrack old = read_block_track(file, id);
    ASSERT_EQ(old.size(), 2u) << id;
    EXPECT_DOUBLE_EQ(old.fcy[1], 40.0) << id;
    EXPECT_DOUBLE_EQ(old.penetration[1], 0.001) << id;
    EXPECT_DOUBLE_EQ(old.ke_grains[1], 0.1) << id;
    ASSERT_EQ(old.torque.size(), 2u) << id;
    EXPECT_TRUE(std::isnan(old.torque[0]) && std::isnan(old.torque[1])) << id;
    EXPECT_TRUE(std::isnan(old.overlap_d_max[1])) << id;
    EXPECT_TRUE(std::isnan(old.block_mass_kg)) << id;
  }
}

TEST_F(BlockTrackFile, MalformedTracksNameTheFileAndTheTrack) {
  const std::string file = path("bad.h5");
  {
    h5::File f(file, h5::File::Mode::kTruncate);
    f.write("/dem/tracks/narrow", std::vector<double>(22, 0.0), {2, 11});
    f.set_attr("/dem/tracks/narrow", "columns", kLegacyColumns);
    f.write("/dem/tracks/timeless", std::vector<double>(4, 0.0), {2, 2});
    f.set_attr("/dem/tracks/timeless", "columns", "x[m],y[m]");
    f.write("/dem/tracks/mm", std::vector<double>(4, 0.0), {2, 2});
    f.set_attr("/dem/tracks/mm", "columns", "t[s],penetration[mm]");
    f.write("/dem/tracks/flat", std::vector<double>(12, 0.0));
    // Found by fuzz_block_track: attributes of the wrong type, and a mass that does not survive
    // the writer (an infinite one was read, then not written back).
    f.write("/dem/tracks/numeric_columns", std::vector<double>(2, 0.0), {2, 1});
    f.set_attr("/dem/tracks/numeric_columns", "columns", 1.0);
    f.write("/dem/tracks/text_mass", std::vector<double>(2, 0.0), {2, 1});
    f.set_attr("/dem/tracks/text_mass", "columns", "t[s]");
    f.set_attr("/dem/tracks/text_mass", "block_mass_kg", std::string("2.9"));
    f.write("/dem/tracks/infinite_mass", std::vector<double>(2, 0.0), {2, 1});
    f.set_attr("/dem/tracks/infinite_mass", "columns", "t[s]");
    f.set_attr("/dem/tracks/infinite_mass", "block_mass_kg", HUGE_VAL);
  }
  for (const char* id : {"numeric_columns", "text_mass", "infinite_mass"}) {
    const InputError e = error_of([&] { read_block_track(file, id); });
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.field(), std::string("/dem/tracks/") + id);
  }
  const InputError narrow = error_of([&] { read_block_track(file, "narrow"); });
  EXPECT_EQ(narrow.file(), file);
  EXPECT_EQ(narrow.field(), "/dem/tracks/narrow");
  EXPECT_NE(narrow.detail().find("2 x 11"), std::string::npos) << narrow.what();
  EXPECT_NE(narrow.detail().find("12 columns"), std::string::npos) << narrow.what();
  const InputError timeless = error_of([&] { read_block_track(file, "timeless"); });
  EXPECT_EQ(timeless.field(), "/dem/tracks/timeless");
  EXPECT_NE(timeless.detail().find("no t column"), std::string::npos) << timeless.what();
  const InputError mm = error_of([&] { read_block_track(file, "mm"); });
  EXPECT_NE(mm.detail().find("penetration[m]"), std::string::npos) << mm.what();
  const InputError flat = error_of([&] { read_block_track(file, "flat"); });
  EXPECT_NE(flat.detail().find("rank 1"), std::string::npos) << flat.what();
  const InputError missing = error_of([&] { read_block_track(file, "nothing"); });
  EXPECT_EQ(missing.field(), "/dem/tracks/nothing");

  // A CSV impact set has no tracks.
  const std::string csv = path("set.csv");
  std::ofstream(csv) << "id,shape\n";
  EXPECT_TRUE(block_track_ids(csv).empty());
  EXPECT_TRUE(block_track_ids(path("absent.h5")).empty());
  EXPECT_EQ(error_of([&] { read_block_track(csv, "C01"); }).file(), csv);
}

TEST(BlockTrackShipped, OldAndNewCampaignFilesReadByTheirColumns) {
  // lab-cylinders.h5 was written before the torque: twelve columns, torque NaN.
  const BlockTrack old = read_block_track(kResolved + "lab-cylinders.h5", "C01");
  EXPECT_EQ(old.size(), 430u);
  EXPECT_TRUE(std::isnan(old.torque[100]));
  EXPECT_TRUE(std::isfinite(old.fcy[100]));
  // The stiffness plateau keeps the torque and the grains' largest overlap.
  const std::string plateau = kResolved + "stiffness-plateau.h5";
  const auto ids = block_track_ids(plateau);
  ASSERT_FALSE(ids.empty());
  const BlockTrack now = read_block_track(plateau, ids.front());
  ASSERT_GT(now.size(), 100u);
  bool torque = false;
  for (std::size_t i = 0; i < now.size(); ++i) {
    EXPECT_TRUE(std::isfinite(now.overlap_d_max[i])) << i;
    torque = torque || (std::isfinite(now.torque[i]) && now.torque[i] != 0);
  }
  EXPECT_TRUE(torque);
}

}  // namespace
}  // namespace ricochet
