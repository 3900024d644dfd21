// The results file of `ricochet dem drop --out` (src-ext/drop_store): rows and tracks appended
// one drop at a time read back as written (what a resumed study relies on), and a damaged file
// is reported with its name and line. No LIGGGHTS.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/error.hpp"
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
