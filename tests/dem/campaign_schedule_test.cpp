// The campaign's schedule (src-ext/campaign_schedule.hpp) without LIGGGHTS: the order, and the
// claims of several groups against a bed cache of empty files (bed_cached needs only that the
// .restart and .params exist; a held .lock is a bed being built).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "bed.hpp"
#include "campaign_schedule.hpp"
#include "support/temp_dir_test.hpp"

namespace {

using namespace ricochet::dem;

TEST(CampaignSchedule,
     OneGroupKeepsTheDesignsOrderSeveralPutCachedBedsFirstAndABedsImpactsTogether) {
  const std::vector<std::string> keys = {"b", "a", "b", "c", "a"};
  EXPECT_EQ(schedule_order(keys, {0, 0, 0, 1, 0}, 1), (std::vector<int>{0, 1, 2, 3, 4}));
  // c is cached: its impact first; then b's (first pending impact 0), then a's.
  EXPECT_EQ(schedule_order(keys, {0, 0, 0, 1, 0}, 2), (std::vector<int>{3, 0, 2, 1, 4}));
}

class CampaignClaims : public ricochet::test::TempDirTest {
 protected:
  CampaignClaims() : TempDirTest("dem-claims") {}
  void cache(const std::string& key) const {
    std::ofstream(bed_prefix(dir_.string(), key) + ".restart");
    std::ofstream(bed_prefix(dir_.string(), key) + ".params");
  }
  std::string claims() const { return (dir_ / "campaign.h5.claims").string(); }
};

// Two groups: the cached bed's impacts go first; a group that finds none takes an impact of a
// bed nobody builds, not one of the bed the other group is building; only when every remaining
// bed is being built does it wait for one.
TEST_F(CampaignClaims, AFreeGroupTakesACachedBedsImpactElseBuildsABedNobodyBuilds) {
  const std::vector<std::string> keys = {"x", "x", "y", "y", "z"};
  const std::vector<int> order = {0, 1, 2, 3, 4};
  cache("z");
  const std::string cache_dir = dir_.string();
  // `waits`: whether the claim is of a bed another group builds (the log line says so).
  bool waits = true;
  EXPECT_EQ(claim_next(claims(), order, keys, cache_dir, &waits), 4);  // z is cached
  EXPECT_FALSE(waits);
  EXPECT_EQ(claim_next(claims(), order, keys, cache_dir, &waits), 0);  // builds x
  EXPECT_FALSE(waits);
  EXPECT_EQ(claim_next(claims(), order, keys, cache_dir, &waits), 2);  // x is taken: builds y
  EXPECT_FALSE(waits);
  EXPECT_EQ(claim_next(claims(), order, keys, cache_dir, &waits), 1);  // all taken: waits for x
  EXPECT_TRUE(waits);
  cache("y");  // y is built meanwhile
  EXPECT_EQ(claim_next(claims(), order, keys, cache_dir, &waits), 3);
  EXPECT_FALSE(waits);
  EXPECT_EQ(claim_next(claims(), order, keys, cache_dir, &waits), -1);
  EXPECT_FALSE(waits);
  std::ifstream in(claims());
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(all, "4\n0\n2\n1\n3\n");
}

// A bed that another process is building (it holds the bed's lock, as ensure_bed does) is not
// built a second time: the group takes the other bed first.
TEST_F(CampaignClaims, ABedAnotherProcessBuildsIsLeftToIt) {
  const std::vector<std::string> keys = {"x", "y"};
  const int fd = ::open((bed_prefix(dir_.string(), "x") + ".lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  bool waits = true;
  EXPECT_EQ(claim_next(claims(), {0, 1}, keys, dir_.string(), &waits), 1);
  EXPECT_FALSE(waits);
  EXPECT_EQ(claim_next(claims(), {0, 1}, keys, dir_.string(), &waits), 0);  // then waits for x
  EXPECT_TRUE(waits);
  ::close(fd);
}

TEST_F(CampaignClaims, AnUnwritableClaimsFileIsAnErrorNamingIt) {
  const std::string path = (dir_ / "no-such-folder" / "c.claims").string();
  try {
    claim_next(path, {0}, {"x"}, dir_.string());
    FAIL() << "claimed without a claims file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
