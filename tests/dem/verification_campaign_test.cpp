// scripts/verification-campaign.py: the design it writes from a grain calibration is read by the
// campaign reader as the plan asks (docs/resolved-model.md, "Recalibration with what sand has"):
// every lab state once, release k on the bed of replica seed k mod 3, the calibrated grains (and
// the tied parameter its source's value), the sampled campaign's stiffness, window and first
// position; with --blind-triangles, the blind triangle check on the same grains; with
// --states-from, the same grains at another campaign's states and positions (issue 33), also on a
// longer bed with every landing point kept; with --sets, the same grains as the sphere drop's --set
// assignments (issue 33's Katsuragi-Durian drop on that bed). And a calibrated parameter the
// campaign did not sample is refused, naming the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "campaign_design.hpp"
#include "common/error.hpp"
#include "dem_support.hpp"
#include "drop_study.hpp"
#include "impact/impact_set.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::dem;
namespace fs = std::filesystem;

const std::string kSource = RICOCHET_SOURCE_DIR;

int run_script(const fs::path& json, const fs::path& out, const fs::path& err,
               const std::string& lab = "cylinders.csv", const std::string& extra = "") {
  const std::string cmd = "python3 " + kSource + "/scripts/verification-campaign.py " + kSource +
                          "/liggghts-inputs/campaigns/sand-calibration-1.5e9.toml " +
                          json.string() + " " + kSource + "/data/lab/" + lab + " --beds 3 " +
                          "--name check --out " + out.string() + extra + " > /dev/null 2> " +
                          err.string();
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A fresh folder holding cal.json, a calibration of the six sampled parameters.
fs::path calibration_folder(const std::string& prefix) {
  // python3 is a required package (scripts/packages.txt); Debian 12's 3.11 has tomllib.
  EXPECT_EQ(std::system("python3 -c 'import tomllib' 2> /dev/null"), 0)
      << "the script needs python3 >= 3.11 (tomllib)";
  const fs::path dir = fs::temp_directory_path() / (prefix + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "cal.json")
      << R"({"calibrated": {"bed.mu_gg": 0.612345, "bed.mur_gg": 0.31, "block.mu_gb": 0.52,
           "bed.e_gg": 0.71, "block.e_gb": 0.64, "bed.mu_pour": 0.2}})";
  return dir;
}

TEST(VerificationCampaign, EveryLabStateOnThreeBedsOfTheCalibratedGrains) {
  const fs::path dir = calibration_folder("dem-verify-");
  ASSERT_EQ(run_script(dir / "cal.json", dir / "design.toml", dir / "err"), 0);
  const CampaignDesign d = read_campaign_design((dir / "design.toml").string(), test::decks());
  const ImpactSet lab = read_impact_set(kSource + "/data/lab/cylinders.csv");
  ASSERT_EQ(d.impacts.size(), lab.size());
  EXPECT_EQ(d.extract.window, "ground");
  for (std::size_t k = 0; k < lab.size(); ++k) {
    const ImpactSpec& s = d.impacts[k];
    EXPECT_EQ(s.id, lab.impacts[k].id);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(s.vin[c], lab.impacts[k].vin[c]) << s.id;
    ASSERT_TRUE(s.seed.has_value());
    EXPECT_EQ(*s.seed, static_cast<std::int64_t>(k % 3)) << s.id;
    EXPECT_DOUBLE_EQ(std::stod(s.params.bed.at("E_grain_Pa")), 1.5e9);
    EXPECT_DOUBLE_EQ(std::stod(s.params.bed.at("mu_gg")), 0.6123);  // 4 significant digits
    EXPECT_DOUBLE_EQ(std::stod(s.params.bed.at("mu_pour")), 0.2);
    EXPECT_DOUBLE_EQ(std::stod(s.params.block.at("e_gb")), 0.64);
    EXPECT_DOUBLE_EQ(std::stod(s.params.block.at("mur_gb")), 0.31);  // tied to bed.mur_gg
    EXPECT_DOUBLE_EQ(std::stod(s.params.run.at("x_impact_frac")), 0.26);
  }
  // The blind triangles: every lab triangle once, one stratified orientation each over the
  // prism's period, on the verification's first bed, the force window and 25 ms of free flight.
  ASSERT_EQ(run_script(dir / "cal.json", dir / "tri.toml", dir / "err", "triangles.csv",
                       " --blind-triangles"),
            0);
  const CampaignDesign t = read_campaign_design((dir / "tri.toml").string(), test::decks());
  const ImpactSet tri = read_impact_set(kSource + "/data/lab/triangles.csv");
  ASSERT_EQ(t.impacts.size(), tri.size());
  EXPECT_EQ(t.extract.window, "force");
  std::set<double> alphas;
  for (std::size_t k = 0; k < tri.size(); ++k) {
    const ImpactSpec& s = t.impacts[k];
    EXPECT_EQ(s.shape, "triangle");
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(s.vin[c], tri.impacts[k].vin[c]) << k;
    EXPECT_LE(std::abs(s.alpha_in_rad), M_PI / 3 + 1e-12);
    alphas.insert(s.alpha_in_rad);
    EXPECT_EQ(s.seed.value_or(-1), 0);
    EXPECT_DOUBLE_EQ(std::stod(s.params.run.at("t_pre_s")), 0.025);
    EXPECT_DOUBLE_EQ(std::stod(s.params.bed.at("mu_gg")), 0.6123);
  }
  EXPECT_EQ(alphas.size(), tri.size());
  // Issue 33's force campaign: the same grains at the speed campaign's 9 states x 3 positions,
  // all on the verification's first bed.
  const std::string speeds = kSource + "/liggghts-inputs/campaigns/speeds-calibrated-long.toml";
  ASSERT_EQ(run_script(dir / "cal.json", dir / "speeds.toml", dir / "err", "cylinders.csv",
                       " --states-from " + speeds),
            0);
  const CampaignDesign v = read_campaign_design((dir / "speeds.toml").string(), test::decks());
  const CampaignDesign source = read_campaign_design(speeds, test::decks());
  ASSERT_EQ(v.impacts.size(), 27u);
  ASSERT_EQ(v.impacts.size(), source.impacts.size());
  for (std::size_t k = 0; k < v.impacts.size(); ++k) {
    const ImpactSpec& s = v.impacts[k];
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(s.vin[c], source.impacts[k].vin[c]) << k;
    EXPECT_EQ(s.params.run.at("x_impact_frac"), source.impacts[k].params.run.at("x_impact_frac"));
    EXPECT_EQ(s.seed.value_or(-1), 0);
    EXPECT_DOUBLE_EQ(std::stod(s.params.bed.at("E_grain_Pa")), 1.5e9);
    EXPECT_DOUBLE_EQ(std::stod(s.params.bed.at("mu_gg")), 0.6123);
  }
  // --bed-length-m: a longer bed, every block landing at the same distance from the back wall.
  ASSERT_EQ(run_script(dir / "cal.json", dir / "long.toml", dir / "err", "cylinders.csv",
                       " --states-from " + speeds + " --bed-length-m 1.5"),
            0);
  const CampaignDesign l = read_campaign_design((dir / "long.toml").string(), test::decks());
  ASSERT_EQ(l.impacts.size(), source.impacts.size());
  for (std::size_t k = 0; k < l.impacts.size(); ++k) {
    EXPECT_DOUBLE_EQ(std::stod(l.impacts[k].params.bed.at("Lx_m")), 1.5);
    EXPECT_NEAR(1.5 * std::stod(l.impacts[k].params.run.at("x_impact_frac")),
                1.0 * std::stod(source.impacts[k].params.run.at("x_impact_frac")), 1e-5)
        << k;
  }
  EXPECT_EQ(run_script(dir / "cal.json", dir / "short.toml", dir / "err", "cylinders.csv",
                       " --bed-length-m 0.1"),
            2);
  std::ofstream(dir / "bad.json") << R"({"calibrated": {"bed.H_m": 0.3}})";
  EXPECT_EQ(run_script(dir / "bad.json", dir / "bad.toml", dir / "err"), 2);
  std::ifstream err(dir / "err");
  const std::string message((std::istreambuf_iterator<char>(err)), {});
  EXPECT_NE(message.find("bad.json: bed.H_m is not a [design.sample] parameter"), std::string::npos)
      << message;
  fs::remove_all(dir);
}

// The active zone's check (docs/resolved-model.md, "Active zone"): the first four releases that
// the verification hits on its bed of replica seed 0, each on exactly that bed twice, the whole
// bed and the zone, with ids that `ricochet paired --base whole- --against zone0.3-` pairs; and
// --active-zone-m puts the zone on every impact of the verification. A zone outside [0.05, 5] m
// is refused.
TEST(VerificationCampaign, TheActiveZoneCheckIsTheVerificationsFirstBedTwice) {
  const fs::path dir = calibration_folder("dem-zone-");
  ASSERT_EQ(run_script(dir / "cal.json", dir / "verify.toml", dir / "err", "cylinders.csv",
                       " --bed-length-m 1.5"),
            0);
  ASSERT_EQ(run_script(dir / "cal.json", dir / "zone.toml", dir / "err", "cylinders.csv",
                       " --bed-length-m 1.5 --zone-check 0.3"),
            0);
  const CampaignDesign v = read_campaign_design((dir / "verify.toml").string(), test::decks());
  const CampaignDesign z = read_campaign_design((dir / "zone.toml").string(), test::decks());
  const std::vector<std::string> releases = {"C01", "C04", "C07", "C10"};
  ASSERT_EQ(z.impacts.size(), 2 * releases.size());
  for (std::size_t k = 0; k < z.impacts.size(); ++k) {
    const ImpactSpec& s = z.impacts[k];
    const ImpactSpec& same = v.impacts[3 * (k / 2)];  // release 3j: the verification's bed 0
    ASSERT_EQ(same.id, releases[k / 2]);
    EXPECT_EQ(s.id, (k % 2 == 0 ? "whole-" : "zone0.3-") + same.id);
    EXPECT_EQ(s.seed.value_or(-1), 0);
    EXPECT_EQ(s.params.bed, same.params.bed) << s.id;  // the same bed, hence the same cache key
    EXPECT_EQ(s.params.block, same.params.block) << s.id;
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(s.vin[c], same.vin[c]) << s.id;
    EXPECT_EQ(s.params.run.at("x_impact_frac"), same.params.run.at("x_impact_frac"));
    const auto zone = s.params.run.find("active_zone_m");
    if (k % 2 == 0)
      EXPECT_TRUE(zone == s.params.run.end() || std::stod(zone->second) == 0.0) << s.id;
    else
      EXPECT_DOUBLE_EQ(std::stod(zone->second), 0.3) << s.id;
  }
  ASSERT_EQ(run_script(dir / "cal.json", dir / "zoned.toml", dir / "err", "cylinders.csv",
                       " --bed-length-m 1.5 --active-zone-m 0.3"),
            0);
  const CampaignDesign zoned = read_campaign_design((dir / "zoned.toml").string(), test::decks());
  ASSERT_EQ(zoned.impacts.size(), v.impacts.size());
  for (const ImpactSpec& s : zoned.impacts)
    EXPECT_DOUBLE_EQ(std::stod(s.params.run.at("active_zone_m")), 0.3) << s.id;
  EXPECT_EQ(run_script(dir / "cal.json", dir / "bad.toml", dir / "err", "cylinders.csv",
                       " --zone-check 0.01"),
            2);
  fs::remove_all(dir);
}

// The triangles' active-zone check (amended 2026-12-06): --id-prefix gives the blind design's
// states and stratified orientations under prefixed ids, with the zone on each, and
// select_impacts (`dem campaign --only`) keeps the chosen impacts of the whole design with the
// specs the whole design gives them, in its order; an id it lacks is refused, naming it.
TEST(VerificationCampaign, TheTrianglesZoneArmIsTheBlindDesignUnderAPrefix) {
  const fs::path dir = calibration_folder("dem-trizone-");
  ASSERT_EQ(run_script(dir / "cal.json", dir / "blind.toml", dir / "err", "triangles.csv",
                       " --blind-triangles --bed-length-m 1.5"),
            0);
  ASSERT_EQ(run_script(dir / "cal.json", dir / "zone.toml", dir / "err", "triangles.csv",
                       " --blind-triangles --bed-length-m 1.5 --active-zone-m 0.3"
                       " --id-prefix zone0.3-"),
            0);
  const CampaignDesign b = read_campaign_design((dir / "blind.toml").string(), test::decks());
  const CampaignDesign z = read_campaign_design((dir / "zone.toml").string(), test::decks());
  ASSERT_EQ(b.impacts.size(), z.impacts.size());
  for (std::size_t k = 0; k < b.impacts.size(); ++k) {
    const ImpactSpec &w = b.impacts[k], &s = z.impacts[k];
    EXPECT_EQ(s.id, "zone0.3-" + w.id);
    EXPECT_EQ(s.alpha_in_rad, w.alpha_in_rad) << s.id;  // bit for bit: the same sample
    for (int c = 0; c < 3; ++c) EXPECT_EQ(s.vin[c], w.vin[c]) << s.id;
    EXPECT_EQ(s.params.bed, w.params.bed) << s.id;  // the same bed and cache key
    EXPECT_EQ(s.params.block, w.params.block) << s.id;
    EXPECT_DOUBLE_EQ(std::stod(s.params.run.at("active_zone_m")), 0.3) << s.id;
    EXPECT_EQ(w.params.run.count("active_zone_m"), 0u) << w.id;
  }
  const CampaignDesign only = select_impacts(b, {"T03", "T01", "T02"});
  ASSERT_EQ(only.impacts.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(only.impacts[k].id, b.impacts[k].id);  // the design's order, not the list's
    EXPECT_EQ(only.impacts[k].alpha_in_rad, b.impacts[k].alpha_in_rad);
  }
  try {
    (void)select_impacts(z, {"zone0.3-T01", "T01"});
    ADD_FAILURE() << "an id the design lacks was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'T01' is not an impact"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("zone0.3-T31"), std::string::npos) << e.what();
  }
  EXPECT_EQ(run_script(dir / "cal.json", dir / "bad.toml", dir / "err", "cylinders.csv",
                       " --id-prefix zone0.3-"),
            2);  // only with --blind-triangles
  fs::remove_all(dir);
}

// The sphere drop on the calibrated grains takes them as `dem drop --set` assignments: every one
// is accepted by the drop's own parser and carries the calibrated value (4 digits), the tie and
// the sampled campaign's stiffness.
TEST(VerificationCampaign, TheCalibratedGrainsAsTheDropsSetAssignments) {
  const fs::path dir = calibration_folder("dem-sets-");
  const std::string cmd = "python3 " + kSource + "/scripts/verification-campaign.py " + kSource +
                          "/liggghts-inputs/campaigns/sand-calibration-1.5e9.toml " +
                          (dir / "cal.json").string() + " --sets > " + (dir / "sets").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(dir / "sets");
  std::vector<std::string> sets;
  for (std::string line; std::getline(in, line);) sets.push_back(line);
  ASSERT_EQ(sets.size(), 8u);  // E_grain_Pa, the six calibrated, the tie
  const DropStudySets parsed = parse_drop_sets(test::decks(), sets);
  EXPECT_DOUBLE_EQ(std::stod(parsed.base.bed.at("E_grain_Pa")), 1.5e9);
  EXPECT_DOUBLE_EQ(std::stod(parsed.base.bed.at("mu_gg")), 0.6123);
  EXPECT_DOUBLE_EQ(std::stod(parsed.base.bed.at("mu_pour")), 0.2);
  EXPECT_DOUBLE_EQ(std::stod(parsed.base.block.at("e_gb")), 0.64);
  EXPECT_DOUBLE_EQ(std::stod(parsed.base.block.at("mur_gb")), 0.31);  // tied to bed.mur_gg
  fs::remove_all(dir);
}

}  // namespace
