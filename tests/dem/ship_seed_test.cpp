// scripts/ship-beds.sh and scripts/seed-shipped.sh: what a campaign still needs leaves one machine
// as plain files and comes back on the next one byte for byte (docs/resolved-model.md,
// "Checkpoints", "Across machines"). The scripts run from a copy of the repository's scripts/ in a
// temporary root (ship-beds.sh writes under ROOT/data/resolved/beds/), with a stand-in for the
// program's dry run that lists the design's impacts: no LIGGGHTS. A complete bed, a bed build's
// checkpoint and an impact's checkpoint in flight are shipped and seeded into an empty results
// folder; a newer checkpoint replaces the older one, and what is no longer needed leaves.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

const std::string kSource = RICOCHET_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

// Bytes that xz cannot shrink to nothing: a restart file's stand-in.
std::string payload(const std::string& tag, int n) {
  std::string s;
  unsigned x = 12345;
  for (int i = 0; i < n; ++i) {
    x = x * 1103515245u + 12345u;
    s += static_cast<char>(x >> 24);
  }
  return tag + s;
}

int run(const std::string& cmd) {
  const int status = std::system((cmd + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class ShipSeed : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("ship-seed-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "scripts");
    for (const char* s : {"ship-beds.sh", "seed-shipped.sh", "pack-decks.py", "pin-program.sh"})
      fs::copy_file(fs::path(kSource) / "scripts" / s, root_ / "scripts" / s);
    out_ = root_ / "results" / "c";
    write(out_ / "c.h5", "campaign file");
    write(root_ / "design.toml", "design");
  }
  void TearDown() override { fs::remove_all(root_); }

  // The program's dry run as the scripts read it: the cache folder and the impacts still to
  // run (status null) with their beds, and one done.
  void program(const std::string& to_run) {
    const fs::path bin = root_ / "ricochet";
    write(bin, "#!/bin/sh\ncat <<'JSON'\n{\"cache_dir\": \"dem-cache\", \"impacts\": [" + to_run +
                   "{\"id\": \"D\", \"bed_key\": \"dddd\", \"status\": \"rebound\"}]}\nJSON\n");
    fs::permissions(bin, fs::perms::owner_all);
  }
  int ship() {
    return run((root_ / "scripts/ship-beds.sh").string() + " " + (root_ / "design.toml").string() +
               " " + (out_ / "c.h5").string() + " " + (root_ / "ricochet").string());
  }
  fs::path shipped() const { return root_ / "data/resolved/beds/c"; }
  fs::path cache() const { return out_ / "dem-cache"; }
  fs::path work() const { return out_ / "dem-work/c/I1"; }
  // Impact I1 in flight at checkpoint generation `gen` (the driver's files, impact_checkpoint.hpp).
  void in_flight(int gen, const std::string& json, const std::string& restart,
                 const std::string& track) {
    write(work() / "checkpoint.json", json);
    write(work() / ("checkpoint-" + std::to_string(gen) + ".restart"), restart);
    write(work() / "impact.track.txt", track);
  }
  // Both impacts still to run: I1 on bed aaaa, I2 on bed bbbb.
  static constexpr const char* kBothToRun = R"({"id": "I1", "bed_key": "aaaa", "status": null},
                                               {"id": "I2", "bed_key": "bbbb", "status": null},)";

  fs::path root_, out_;
};

TEST_F(ShipSeed, WhatIsInFlightComesBackByteForByteOnAnEmptyMachine) {
  const fs::path cache = this->cache(), work = this->work();
  // bed aaaa complete, bed bbbb building (two checkpoints: the latest goes), impact I1 in flight
  // at generation 3 (its older generation's restart already gone, as the driver leaves it).
  const std::string bed = payload("bed", 4000), ckpt_old = payload("old", 3000),
                    ckpt = payload("ckpt", 3000), restart = payload("restart", 5000);
  write(cache / "bed-aaaa.restart", bed);
  write(cache / "bed-aaaa.params", "params of aaaa\n");
  write(cache / "bed-bbbb.building.ckpt-1-40-0.restart", ckpt_old);
  write(cache / "bed-bbbb.building.ckpt-2-8-1.restart", ckpt);
  write(cache / "bed-bbbb.building.ckpt-new.restart", "being written");
  in_flight(3, "{\"generation\": 3, \"step\": 60000}\n", restart, "t x y\n1 2 3\n");
  write(work / "log.liggghts", "not shipped");
  program(kBothToRun);
  ASSERT_EQ(ship(), 0);
  EXPECT_TRUE(fs::exists(shipped() / "bed-aaaa.restart.xz"));
  EXPECT_TRUE(fs::exists(shipped() / "bed-aaaa.params"));
  EXPECT_TRUE(fs::exists(shipped() / "bed-bbbb.building.ckpt-2-8-1.restart.xz"));
  EXPECT_FALSE(fs::exists(shipped() / "bed-bbbb.building.ckpt-1-40-0.restart.xz"));
  EXPECT_TRUE(fs::exists(shipped() / "impact-I1.gen-3.tar.xz"));
  EXPECT_EQ(read(shipped() / "pinned-in"), "c\n");

  // The next machine: the results folder is gone; seeding brings back every file.
  fs::rename(out_, root_ / "old");
  write(out_ / "c.h5", "campaign file");
  ASSERT_EQ(run((root_ / "scripts/seed-shipped.sh").string() + " " + shipped().string() + " " +
                out_.string() + " " + cache.string()),
            0);
  EXPECT_EQ(read(cache / "bed-aaaa.restart"), bed);
  EXPECT_EQ(read(cache / "bed-aaaa.params"), "params of aaaa\n");
  EXPECT_EQ(read(cache / "bed-bbbb.building.ckpt-2-8-1.restart"), ckpt);
  EXPECT_EQ(read(work / "checkpoint.json"), "{\"generation\": 3, \"step\": 60000}\n");
  EXPECT_EQ(read(work / "checkpoint-3.restart"), restart);
  EXPECT_EQ(read(work / "impact.track.txt"), "t x y\n1 2 3\n");
  EXPECT_FALSE(fs::exists(work / "log.liggghts"));
  for (const auto& e : fs::recursive_directory_iterator(out_))
    EXPECT_EQ(e.path().string().find(".seeding"), std::string::npos) << e.path();
  // Seeding again changes nothing that is there (a local checkpoint is newer than the shipped).
  write(work / "checkpoint.json", "{\"generation\": 4}\n");
  ASSERT_EQ(run((root_ / "scripts/seed-shipped.sh").string() + " " + shipped().string() + " " +
                out_.string() + " " + cache.string()),
            0);
  EXPECT_EQ(read(work / "checkpoint.json"), "{\"generation\": 4}\n");
}

TEST_F(ShipSeed, ANewerCheckpointReplacesTheOlderAndWhatIsDoneLeaves) {
  const fs::path cache = this->cache(), work = this->work();
  write(cache / "bed-bbbb.building.ckpt-1-40-0.restart", payload("a", 2000));
  in_flight(1, "{\"generation\": 1}\n", payload("r1", 2000), "t\n");
  program(kBothToRun);
  ASSERT_EQ(ship(), 0);
  EXPECT_TRUE(fs::exists(shipped() / "bed-bbbb.building.ckpt-1-40-0.restart.xz"));
  EXPECT_TRUE(fs::exists(shipped() / "impact-I1.gen-1.tar.xz"));
  // Later: the build went on and the impact checkpointed again.
  fs::remove(cache / "bed-bbbb.building.ckpt-1-40-0.restart");
  write(cache / "bed-bbbb.building.ckpt-1-80-0.restart", payload("b", 2000));
  fs::remove(work / "checkpoint-1.restart");
  write(work / "checkpoint-2.restart", payload("r2", 2000));
  write(work / "checkpoint.json", "{\"generation\": 2}\n");
  ASSERT_EQ(ship(), 0);
  EXPECT_FALSE(fs::exists(shipped() / "bed-bbbb.building.ckpt-1-40-0.restart.xz"));
  EXPECT_TRUE(fs::exists(shipped() / "bed-bbbb.building.ckpt-1-80-0.restart.xz"));
  EXPECT_FALSE(fs::exists(shipped() / "impact-I1.gen-1.tar.xz"));
  EXPECT_TRUE(fs::exists(shipped() / "impact-I1.gen-2.tar.xz"));
  // Later still: bed bbbb is complete and I1 is done (not in the dry run's to-run list).
  write(cache / "bed-bbbb.restart", payload("bed", 2000));
  write(cache / "bed-bbbb.params", "params of bbbb\n");
  program(R"({"id": "I2", "bed_key": "bbbb", "status": null},)");
  ASSERT_EQ(ship(), 0);
  EXPECT_TRUE(fs::exists(shipped() / "bed-bbbb.params"));
  EXPECT_FALSE(fs::exists(shipped() / "bed-bbbb.building.ckpt-1-80-0.restart.xz"));
  EXPECT_FALSE(fs::exists(shipped() / "impact-I1.gen-2.tar.xz"));
}

// A bed's key hashes the bed decks' text, so the beds are shipped with the decks the campaign
// pinned, and a new machine pins those for that results folder, not its tree's, which may have
// been edited since (2026-12-07: a shipped bed went unfound under the tree's decks). Another
// folder still pins the tree's.
TEST_F(ShipSeed, TheBedsTravelWithTheDecksThatKeyThem) {
  write(cache() / "bed-aaaa.restart", payload("bed", 2000));
  write(cache() / "bed-aaaa.params", "params of aaaa\n");
  write(out_ / "pinned/liggghts-inputs/bed/in.bed", "the pinned bed deck\n");
  write(out_ / "pinned/liggghts-inputs/common/walls.in", "the pinned walls\n");
  program(kBothToRun);
  ASSERT_EQ(ship(), 0);
  ASSERT_TRUE(fs::exists(shipped() / "pinned-decks.tar.xz"));
  // The same decks packed again: the same bytes (git sees no change at every session's end).
  const std::string first = read(shipped() / "pinned-decks.tar.xz");
  ASSERT_EQ(ship(), 0);
  EXPECT_EQ(read(shipped() / "pinned-decks.tar.xz"), first);

  // The next machine: no results folder, the tree's decks edited since, a program to pin.
  fs::remove_all(out_);
  write(root_ / "liggghts-inputs/bed/in.bed", "the tree's edited bed deck\n");
  write(root_ / "build/cli/ricochet", "program");
  const auto pin = [&](const std::string& folder) {
    return run("bash -c 'source " + (root_ / "scripts/pin-program.sh").string() +
               " && pin_program " + root_.string() + " " +
               (root_ / "results" / folder / "pinned").string() + "'");
  };
  ASSERT_EQ(pin("c"), 0);
  EXPECT_EQ(read(out_ / "pinned/liggghts-inputs/bed/in.bed"), "the pinned bed deck\n");
  EXPECT_EQ(read(out_ / "pinned/liggghts-inputs/common/walls.in"), "the pinned walls\n");
  EXPECT_EQ(read(out_ / "pinned/ricochet"), "program");
  ASSERT_EQ(pin("other"), 0);
  EXPECT_EQ(read(root_ / "results/other/pinned/liggghts-inputs/bed/in.bed"),
            "the tree's edited bed deck\n");
}

}  // namespace
