// The campaign file shared by processes: the groups of an MPI campaign (and a session copying the
// file of a running campaign) read it while another process appends. HDF5 refuses to open a file
// for writing while another process has it open (it does not wait), so readers take the shared
// lock on PATH.lock and writers the exclusive one. Before readers locked, a campaign of two
// groups died in CI with "cannot open file" when one group counted the index just as the other
// marked its next impact running.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>

#include "campaign.hpp"
#include "campaign_store.hpp"
#include "common/error.hpp"
#include "impact/impact_set.hpp"
#include "impact_run.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::dem;
namespace fs = std::filesystem;

constexpr int kAppends = 25;

// A fresh folder for one test's campaign file.
std::string fresh_campaign(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return (d / "campaign.h5").string();
}

// Forks a child that runs `write` on `path` while this process reads the index until the
// child ends; expects the child to succeed (its message, if not, on stderr) and no read to fail.
void read_while_child_writes(const std::string& path, const std::function<void()>& write) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      write();
    } catch (const std::exception& e) {
      std::cerr << "child: " << e.what() << "\n";
      ::_exit(1);
    }
    ::_exit(0);
  }
  int reads = 0, failures = 0, status = 0;
  std::string first_failure;
  while (::waitpid(child, &status, WNOHANG) == 0) {
    try {
      read_campaign_index(path);
      ++reads;
    } catch (const std::exception& e) {
      if (failures++ == 0) first_failure = e.what();
    }
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the writer failed (its message is on stderr)";
  EXPECT_EQ(failures, 0) << first_failure;
  EXPECT_GT(reads, 0);
}

TEST(DemCampaignStore, ReaderAndWriterInTwoProcessesNeverCollide) {
  const std::string path = fresh_campaign("dem-store-test");
  // The child appends kAppends impacts, each marked running first, as a campaign group does.
  read_while_child_writes(path, [&] {
    for (int i = 0; i < kAppends; ++i) {
      ImpactSpec spec;
      spec.id = "impact-" + std::to_string(i);
      mark_running(path, spec.id, "work");
      ImpactResult r;
      r.id = spec.id;
      r.status = "ok";
      for (int k = 0; k < 50; ++k)
        for (const auto& name : BlockTrack::column_names())
          r.track.column(name)->push_back(1e-3 * k);
      append_result(path, r, spec, "concurrency-test");
    }
  });
  const auto index = read_campaign_index(path);
  ASSERT_EQ(index.size(), static_cast<std::size_t>(kAppends));
  EXPECT_EQ(index.back().id, "impact-" + std::to_string(kAppends - 1));
  fs::remove_all(fs::path(path).parent_path());
}

// A campaign file of three rebounds, as a finished campaign leaves it; its entries.
std::vector<CampaignEntry> three_rebounds(const std::string& path) {
  for (int i = 0; i < 3; ++i) {
    ImpactSpec spec;
    spec.id = "impact-" + std::to_string(i);
    ImpactResult r;
    r.id = spec.id;
    r.status = "rebound";
    r.impact.shape = "cylinder";
    r.impact.vin = {2.0, -3.0 - i, 1.0};
    r.impact.vout = {1.5, 0.5, -20.0};
    r.impact.extra.assign(impact_extra_names().size(), 0.0);
    append_result(path, r, spec, "rewrite-test");
  }
  return read_campaign_index(path);
}

// A finished campaign run again: world rank 0 rewrites the impact set (rewrite_impact_set) while
// the other ranks read the index to list the end-wall reruns. The rewrite took no lock until
// 2026-12-02, and every two-rank restart of the sand calibration died in rank 0's H5Fopen.
TEST(DemCampaignStore, RewriteAndReaderInTwoProcessesNeverCollide) {
  const std::string path = fresh_campaign("dem-rewrite-test");
  const auto entries = three_rebounds(path);
  ASSERT_EQ(entries.size(), 3u);
  read_while_child_writes(path, [&] {
    for (int i = 0; i < kAppends; ++i) rewrite_impact_set(path, entries, "rewrite-test");
  });
  EXPECT_EQ(read_campaign_index(path).size(), 3u);
  fs::remove_all(fs::path(path).parent_path());
}

// A campaign resumed on a new machine starts from its shipped copy, which has no PATH.lock. Its
// first reader used to read unlocked while another rank's first writer created the lock, and the
// writer's H5Fopen failed (2026-12-02: every two-rank start of the sand calibration from its
// shipped file). A reader now creates the lock file where it can.
TEST(DemCampaignStore, AShippedCopyWithoutItsLockFileNeverCollides) {
  const std::string path = fresh_campaign("dem-unlocked-copy-test");
  const auto entries = three_rebounds(path);
  ASSERT_EQ(entries.size(), 3u);
  fs::remove(path + ".lock");
  EXPECT_EQ(read_campaign_index(path).size(), 3u);
  EXPECT_TRUE(fs::exists(path + ".lock")) << "the first reader takes a lock a writer also takes";
  // The race itself, from the first access on, several times.
  for (int round = 0; round < 5; ++round) {
    fs::remove(path + ".lock");
    read_while_child_writes(path, [&] {
      for (int i = 0; i < 5; ++i) rewrite_impact_set(path, entries, "rewrite-test");
    });
  }
  fs::remove_all(fs::path(path).parent_path());
}

// `dem campaign --forget`: a record a fault of the program wrote (2026-12-06: T01 of the blind
// triangles recorded not_inserted on resuming) is removed with its track, the rest of the file
// kept row for row, so that the next run of the design runs it again; an id the file lacks
// removes nothing.
TEST(DemCampaignStore, ForgettingAnImpactRemovesItsRowAndTrackAndKeepsTheRest) {
  const std::string path = fresh_campaign("dem-forget-test");
  for (int i = 0; i < 3; ++i) {
    ImpactSpec spec;
    spec.id = "impact-" + std::to_string(i);
    ImpactResult r;
    r.id = spec.id;
    r.status = i == 1 ? "not_inserted" : "rebound";
    r.message = i == 1 ? "93977 atoms after the block insertion" : "";
    r.impact.shape = "cylinder";
    r.impact.vin = {2.0, -3.0 - i, 1.0};
    r.impact.vout = {1.5, 0.5 + i, -20.0};
    r.impact.extra.assign(impact_extra_names().size(), 0.0);
    for (int k = 0; k < 5; ++k)
      for (const auto& name : BlockTrack::column_names())
        r.track.column(name)->push_back(1e-3 * k + i);
    append_result(path, r, spec, "forget-test");
  }
  const auto before = read_campaign_index(path);
  EXPECT_THROW(forget_impacts(path, {"impact-1", "impact-9"}), InputError);
  EXPECT_EQ(read_campaign_index(path).size(), 3u);  // nothing removed
  const auto gone = forget_impacts(path, {"impact-1"});
  ASSERT_EQ(gone.size(), 1u);
  EXPECT_EQ(gone[0].status, "not_inserted");
  const auto after = read_campaign_index(path);
  ASSERT_EQ(after.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const CampaignEntry& want = before[k == 0 ? 0 : 2];
    EXPECT_EQ(after[k].id, want.id);
    EXPECT_EQ(after[k].status, want.status);
    EXPECT_EQ(after[k].params, want.params);
    for (std::size_t c = 0; c < want.values.size(); ++c)
      EXPECT_TRUE(after[k].values[c] == want.values[c] ||
                  (std::isnan(after[k].values[c]) && std::isnan(want.values[c])))
          << after[k].id << " column " << c;
  }
  EXPECT_THROW(read_campaign_track(path, "impact-1"), InputError);
  EXPECT_EQ(read_campaign_track(path, "impact-2").t.front(), 2.0);
  const ImpactSet set = read_impact_set(path);
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.impacts[1].id, "impact-2");
  fs::remove_all(fs::path(path).parent_path());
}

// A resumed impact lacks the grains its checkpoint had lost; the rule that judges every chunk
// judges them (a hundredth of the bed's grains, every block sphere), not the fresh start's count.
TEST(DemCampaignStore, AResumedImpactIsJudgedByTheGrainLossRule) {
  const long bed = 91532, spheres = 2772;
  EXPECT_TRUE(block_inserted(bed + spheres, bed, bed, spheres, false));
  EXPECT_FALSE(block_inserted(bed + spheres - 327, bed - 327, bed, spheres, false));
  EXPECT_TRUE(block_inserted(bed + spheres - 327, bed - 327, bed, spheres, true));  // T01's case
  EXPECT_EQ(acceptable_grain_loss(bed + spheres - 327, bed - 327, bed, spheres), 327);
  EXPECT_EQ(acceptable_grain_loss(bed + spheres - 916, bed - 916, bed, spheres), 916);
  EXPECT_EQ(acceptable_grain_loss(bed + spheres - 917, bed - 917, bed, spheres), -1);  // > 1 %
  EXPECT_FALSE(block_inserted(bed + spheres - 1, bed, bed, spheres, true));  // a sphere lost
}

}  // namespace
