// A plan of throws (`ricochet design --out plan.csv`) as the impacts of a resolved campaign:
// `[design] plan = "plan.csv"` in a campaign design (src-ext/campaign_design.hpp). Only the design
// reader runs: no LIGGGHTS.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "campaign_design.hpp"
#include "common/error.hpp"
#include "params.hpp"

namespace ricochet::dem {
namespace {

namespace fs = std::filesystem;

const Decks& decks() {
  static const Decks d = Decks::locate(std::string(RICOCHET_SOURCE_DIR) + "/liggghts-inputs");
  return d;
}

class CampaignPlan : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ricochet-plan-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // What `ricochet design` writes: comments, then the incident columns only.
    std::ofstream(dir_ / "plan.csv") << "# Ricochet impact set v1: incident states only\n"
                                        "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s]\n"
                                        "D001,cylinder,3.5,-4.25,-30\n"
                                        "D002,cylinder,2.25,-1.5,-80\n"
                                        "D003,triangle,4,-2,-45\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  CampaignDesign read(const std::string& design) {
    const fs::path p = dir_ / "campaign.toml";
    std::ofstream(p) << design;
    return read_campaign_design(p.string(), decks());
  }
  fs::path dir_;
};

TEST_F(CampaignPlan, EachRowIsOneImpactSeededByItsRow) {
  const CampaignDesign d = read("[design]\nplan = \"plan.csv\"\n");  // relative to the design
  ASSERT_EQ(d.impacts.size(), 3u);
  EXPECT_EQ(d.impacts[0].id, "D001");
  EXPECT_EQ(d.impacts[0].shape, "cylinder");
  EXPECT_EQ(d.impacts[0].vin, (Vel3{3.5, -4.25, -30}));
  EXPECT_EQ(d.impacts[2].shape, "triangle");  // each row's own shape
  for (std::size_t i = 0; i < 3; ++i) {
    ASSERT_TRUE(d.impacts[i].seed.has_value());
    EXPECT_EQ(*d.impacts[i].seed, static_cast<std::int64_t>(i));  // replica seed = row index
  }
}

TEST_F(CampaignPlan, SeedsGivenReplaceTheRowIndex) {
  const CampaignDesign d =
      read("[design]\nplan = \"plan.csv\"\nseeds = [7, 8]\nid_prefix = \"p-\"\n");
  ASSERT_EQ(d.impacts.size(), 6u);
  EXPECT_EQ(d.impacts[0].id, "p-D001-s7");
  EXPECT_EQ(*d.impacts[0].seed, 7);
  EXPECT_EQ(*d.impacts[1].seed, 8);
}

TEST_F(CampaignPlan, ABadPlanNamesItsFileAndLine) {
  std::ofstream(dir_ / "bad.csv")
      << "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s]\nD1,cylinder,3,1,-30\n";
  try {
    read("[design]\nplan = \"bad.csv\"\n");
    FAIL() << "a rising block was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "vin_y");
    EXPECT_EQ(e.line(), 2u);
    EXPECT_NE(e.file().find("bad.csv"), std::string::npos);
  }
  EXPECT_THROW(read("[design]\nplan = \"missing.csv\"\n"), InputError);
}

}  // namespace
}  // namespace ricochet::dem
