// The results file of `ricochet dem drop --out` (src-ext/drop_store): rows and tracks appended
// one drop at a time read back as written (what a resumed study relies on), and a damaged file
// is reported with its name and line; torn track records are found. No LIGGGHTS.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include "common/error.hpp"
#include "drop.hpp"
#include "drop_store.hpp"

namespace {

using namespace ricochet::dem;
namespace fs = std::filesystem;

DropResult drop(const std::string& id, double h, double depth) {
  DropResult r;
  r.id = id;
  r.status = "at_rest";
  r.message = "came to rest, \"quoted\", with a comma";
  r.h_drop_m = h;
  r.depth_final_m = depth;
  r.depth_max_m = 1.1 * depth;
  r.grains = 1234;
  r.kd_trajectory = KatsuragiDurianFit{};
  r.kd_trajectory->d1_m = 0.0123;
  for (int i = 0; i < 4; ++i) {
    for (std::size_t c = 0; c < DropTrack::column_names().size(); ++c)
      r.track.column(c).push_back(0.001 * i + c);
  }
  return r;
}

fs::path fresh_dir() {
  const fs::path d = fs::temp_directory_path() / ("drop-store-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(DropStore, RowsAndTracksReadBackAsAppended) {
  const fs::path dir = fresh_dir();
  const DropStore store((dir / "drops.csv").string());
  EXPECT_TRUE(store.done_ids().empty());
  store.append(drop("h0.1", 0.1, 0.012), -1);
  store.append(drop("h0.2", 0.2, 0.015), 3);
  EXPECT_EQ(store.done_ids(), (std::set<std::string>{"h0.1", "h0.2"}));
  const auto rows = store.rows();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_DOUBLE_EQ(rows[1].number("depth_final_m"), 0.015);
  EXPECT_DOUBLE_EQ(rows[1].number("kd_d1_m"), 0.0123);
  EXPECT_EQ(rows[1].text("seed"), "3");
  EXPECT_EQ(rows[0].text("message"), "came to rest, \"quoted\", with a comma");
  EXPECT_TRUE(std::isnan(rows[0].number("kdf_d1_m")));  // no force fit: NaN
  EXPECT_TRUE(std::isnan(rows[0].number("no_such_column")));
  const auto tracks = store.tracks();
  ASSERT_EQ(tracks.size(), 2u);
  ASSERT_EQ(tracks.at("h0.2").size(), 4u);
  EXPECT_DOUBLE_EQ(tracks.at("h0.2").column(2)[3], 2.003);
  EXPECT_EQ(store.tracks_path(), (dir / "drops.tracks.csv").string());
  EXPECT_EQ(store.repose_path(), (dir / "drops.repose.json").string());
  fs::remove_all(dir);
}

TEST(DropStore, DamagedRowNamesFileAndLine) {
  const fs::path dir = fresh_dir();
  const DropStore store((dir / "drops.csv").string());
  store.append(drop("h0.1", 0.1, 0.012), -1);
  std::ofstream((dir / "drops.csv").string(), std::ios::app) << "h0.5,7\n";
  try {
    store.rows();
    FAIL() << "a short row was accepted";
  } catch (const ricochet::InputError& e) {
    EXPECT_EQ(e.file(), store.path());
    EXPECT_EQ(e.line(), 3u);
  }
  fs::remove_all(dir);
}

}  // namespace

namespace {

// A sphere of 4 kg stopped by a constant 120 N upward force, recorded every 16.4 us (the stiff
// bed's drops): Newton holds from record to record.
DropTrack decelerating_track(std::size_t n) {
  DropTrack tr;
  const double dt = 16.4e-6, m = 4.0, f = 120.0, a = f / m - 9.81;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    const std::vector<double> row = {t, 0.2, 0.0, 0.5 * t - 0.5 * a * t * t, 0, 0, -0.5 + a * t, 0,
                                     0, f,   0};
    for (std::size_t c = 0; c < row.size(); ++c) tr.column(c).push_back(row[c]);
  }
  return tr;
}

}  // namespace

// remove_torn_records: a record whose columns from vz on belong to another record (the tear of
// the shipped h = 0.02 m drop) goes, and nothing else does.
TEST(DropTrack, ATornRecordIsRemovedAndACleanTrackIsKept) {
  DropTrack clean = decelerating_track(2000);
  EXPECT_EQ(remove_torn_records(clean, 4.0), 0u);
  EXPECT_EQ(clean.size(), 2000u);
  DropTrack torn = decelerating_track(2000);
  torn.vz[700] = 0.1998;  // an x position written where vz belongs
  torn.fcz[700] = -0.0003;
  EXPECT_EQ(remove_torn_records(torn, 4.0), 1u);
  ASSERT_EQ(torn.size(), 1999u);
  EXPECT_EQ(torn.t[700], clean.t[701]);
  EXPECT_EQ(torn.vz[699], clean.vz[699]);
}

// On the shipped stiff-bed drops (LIGGGHTS tracks, contact forces from grains): the two torn
// records of h = 0.02 m (t = 22.73 ms and 24.06 ms; read off the file: each record's vy is cut
// short and another record's x, y, depth, vx, vy follow, then 1.0 and 5.4 ms are missing) are
// found, and no record of the four clean drops is taken.
TEST(DropTrack, TheShippedStiffBedDropsHoldTwoTornRecords) {
  const DropStore store(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/sphere-drop-1.5e9.csv");
  auto tracks = store.tracks();
  ASSERT_EQ(tracks.size(), 5u);
  const double mass_kg = 7800 * 3.141592653589793 / 6 * 0.1 * 0.1 * 0.1;
  for (auto& [id, tr] : tracks) {
    const DropTrack before = tr;
    const std::size_t removed = remove_torn_records(tr, mass_kg);
    if (id != "h0.02") {
      EXPECT_EQ(removed, 0u) << id;
      continue;
    }
    ASSERT_EQ(removed, 2u);
    std::vector<double> gone;
    for (std::size_t i = 0, k = 0; i < before.size(); ++i) {
      if (k < tr.size() && tr.t[k] == before.t[i]) {
        ++k;
      } else {
        gone.push_back(before.t[i]);
      }
    }
    ASSERT_EQ(gone.size(), 2u);
    EXPECT_NEAR(gone[0], 0.022732, 1e-6);
    EXPECT_NEAR(gone[1], 0.024058, 1e-6);
  }
}
