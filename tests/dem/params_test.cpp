// Deck parameters, bed cache keys and campaign designs: read from the decks themselves, checked
// with errors that name file, line and key.
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "bed.hpp"
#include "campaign.hpp"
#include "common/error.hpp"
#include "dem_support.hpp"
#include "params.hpp"

namespace {

using namespace ricochet::dem;
using ricochet::InputError;
namespace fs = std::filesystem;

using test::decks;

std::string temp_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("dem-params-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

TEST(DeckParams, ReadFromTheDecks) {
  std::set<std::string> bed, block, run;
  for (const auto& p : decks().bed_params) bed.insert(p.name);
  for (const auto& p : decks().block_params) block.insert(p.name);
  for (const auto& p : decks().impact_params) run.insert(p.name);
  for (const char* n : {"E_grain_Pa", "e_gg", "mu_gg", "mur_gg", "r1_m", "f1", "mode", "seed"})
    EXPECT_TRUE(bed.count(n)) << n;
  for (const char* n : {"E_block_Pa", "e_gb", "mu_gb", "mur_gb"}) EXPECT_TRUE(block.count(n)) << n;
  for (const char* n : {"t_max_s", "t_flight_s", "chunk_steps", "dt_scale"})
    EXPECT_TRUE(run.count(n)) << n;
  // The incident state and the wiring are set by the driver, not by --set.
  for (const char* n : {"vx_in_mps", "alpha_in_deg", "bed", "template_in", "deck_dir"})
    EXPECT_FALSE(run.count(n)) << n;
}

// in.bed must write every bed parameter to PREFIX.params: the impact deck reads the bed's grain
// law from there, and a parameter missing from it would silently take no value.
TEST(DeckParams, BedDeckRecordsEveryBedParameter) {
  std::ifstream in(decks().bed_deck);
  std::stringstream s;
  s << in.rdbuf();
  for (const auto& p : decks().bed_params)
    EXPECT_NE(s.str().find("\"variable " + p.name + " string ${" + p.name + "}\""),
              std::string::npos)
        << p.name << " is not written to ${bed}.params by in.bed";
}

TEST(DeckParams, ChecksNamesAndBounds) {
  EXPECT_NO_THROW(check_param(decks(), "bed", "E_grain_Pa", "2e8", "f.toml", 3));
  // The active zone is off at 0, its default; a negative length is refused.
  EXPECT_NO_THROW(check_param(decks(), "run", "active_zone_m", "0", "f.toml", 3));
  EXPECT_NO_THROW(check_param(decks(), "run", "active_zone_m", "0.3", "f.toml", 3));
  EXPECT_THROW(check_param(decks(), "run", "active_zone_m", "-0.1", "f.toml", 3), InputError);
  try {
    check_param(decks(), "bed", "E_grain", "2e8", "f.toml", 7);
    FAIL() << "unknown name accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "f.toml");
    EXPECT_EQ(e.line(), 7u);
    EXPECT_EQ(e.field(), "bed.E_grain");
    EXPECT_NE(e.detail().find("E_grain_Pa"), std::string::npos);  // lists the known names
  }
  EXPECT_THROW(check_param(decks(), "bed", "e_gg", "1.5", "f", 1), InputError);
  EXPECT_THROW(check_param(decks(), "bed", "e_gg", "0", "f", 1), InputError);
  EXPECT_THROW(check_param(decks(), "bed", "mu_gg", "-0.1", "f", 1), InputError);
  EXPECT_THROW(check_param(decks(), "bed", "r1_m", "0", "f", 1), InputError);
  EXPECT_THROW(check_param(decks(), "bed", "E_grain_Pa", "abc", "f", 1), InputError);
  EXPECT_THROW(check_param(decks(), "bed", "nu_grain", "0.5", "f", 1), InputError);
  EXPECT_THROW(check_param(decks(), "bed", "mode", "slice", "f", 1), InputError);
  EXPECT_THROW(check_param(decks(), "bed", "seed", "10001", "f", 1), InputError);  // 73 x 137
  EXPECT_NO_THROW(check_param(decks(), "bed", "seed", "10007", "f", 1));
  EXPECT_THROW(check_param(decks(), "run", "chunk_steps", "10.5", "f", 1), InputError);
  EXPECT_THROW(check_param(decks(), "block", "e_gg", "0.3", "f", 1), InputError);  // wrong section
}

TEST(DeckParams, SetOption) {
  Overrides o;
  apply_set_option(decks(), "bed.E_grain_Pa=1e8", o);
  apply_set_option(decks(), "block.mu_gb=0.4", o);
  apply_set_option(decks(), "run.t_max_s=0.2", o);
  EXPECT_EQ(o.bed.at("E_grain_Pa"), "1e8");
  EXPECT_EQ(o.block.at("mu_gb"), "0.4");
  EXPECT_EQ(o.run.at("t_max_s"), "0.2");
  EXPECT_THROW(apply_set_option(decks(), "E_grain_Pa=1e8", o), InputError);
  EXPECT_THROW(apply_set_option(decks(), "grain.E_grain_Pa=1e8", o), InputError);
}

TEST(BedKey, CanonicalAndSensitive) {
  const auto k0 = bed_key(decks(), {});
  EXPECT_EQ(k0.size(), 16u);
  // The same effective parameters, written differently, name the same bed.
  EXPECT_EQ(bed_key(decks(), {{"E_grain_Pa", "100000000"}}),
            bed_key(decks(), {{"E_grain_Pa", "1e8"}}));
  // Giving a parameter its default value explicitly changes nothing.
  for (const auto& p : decks().bed_params) {
    if (p.name == "e_gg") {
      EXPECT_EQ(bed_key(decks(), {{"e_gg", p.default_value}}), k0);
    }
  }
  EXPECT_NE(bed_key(decks(), {{"E_grain_Pa", "1e8"}}), k0);
  EXPECT_NE(bed_key(decks(), {{"seed", "10007"}}), k0);
}

// A bed being built is seen by its lock (held exclusively by ensure_bed for the whole build, here
// by this test): not cached, and building only while the lock is held.
TEST(BedCache, ABedBeingBuiltIsSeenByItsLock) {
  const fs::path cache = fs::temp_directory_path() / ("dem-building-" + std::to_string(::getpid()));
  fs::remove_all(cache);
  fs::create_directories(cache);
  const std::string key = "0123456789abcdef";
  EXPECT_FALSE(bed_building(cache.string(), key));  // no lock file: never started here
  const std::string lock = bed_prefix(cache.string(), key) + ".lock";
  const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  EXPECT_FALSE(bed_building(cache.string(), key));  // a lock file nobody holds
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  EXPECT_TRUE(bed_building(cache.string(), key));
  EXPECT_FALSE(bed_cached(cache.string(), key));
  ::flock(fd, LOCK_UN);
  ::close(fd);
  EXPECT_FALSE(bed_building(cache.string(), key));
  fs::remove_all(cache);
}

TEST(BedKey, DeckCommandsCountCommentsDoNot) {
  const fs::path root = fs::temp_directory_path() / ("dem-decks-" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::copy(std::string(RICOCHET_SOURCE_DIR) + "/liggghts-inputs", root,
           fs::copy_options::recursive);
  const auto key = [&] { return bed_key(Decks::locate(root.string()), {}); };
  const std::string k0 = key();
  EXPECT_EQ(k0, bed_key(decks(), {}));
  std::ofstream(root / "common/materials.in", std::ios::app) << "\n# a new comment\n\n";
  EXPECT_EQ(key(), k0);
  std::ofstream(root / "common/materials.in", std::ios::app) << "neigh_modify every 1\n";
  EXPECT_NE(key(), k0);
  fs::remove_all(root);
}

TEST(Seeds, PrimesAboveTenThousand) {
  EXPECT_EQ(liggghts_seed(0, 0), 10007);
  EXPECT_EQ(liggghts_seed(0, 1), 10009);
  EXPECT_EQ(liggghts_seed(1, 0), 10037);
  std::set<std::int64_t> seen;
  for (int r = 0; r < 20; ++r)
    for (int s = 0; s < 2; ++s) {
      const auto p = liggghts_seed(r, s);
      EXPECT_TRUE(is_prime(p));
      EXPECT_TRUE(seen.insert(p).second);
    }
}

TEST(Design, ExplicitImpactsAndProduct) {
  const auto path = temp_file("design.toml", R"(
[campaign]
name = "t"
ranks_per_impact = 1
[bed]
E_grain_Pa = 1e8
[run]
t_max_s = 0.2
[[impact]]
id = "one"
vin = [2.9, -2.3, -65.0]
[impact.bed]
e_gg = 0.6
[design]
shape = "triangle"
incident = [[3.0, -2.0, -20.0], [4.0, -3.0, -30.0]]
alpha_in_deg = [0.0, 30.0]
seeds = [0, 1]
[design.vary]
"block.mu_gb" = [0.3, 0.6]
)");
  const auto d = read_campaign_design(path, decks());
  EXPECT_EQ(d.name, "t");
  ASSERT_EQ(d.impacts.size(), 1u + 2 * 2 * 2 * 2);
  EXPECT_EQ(d.impacts[0].id, "one");
  EXPECT_EQ(d.impacts[0].params.bed.at("E_grain_Pa"), "1e+08");
  EXPECT_EQ(d.impacts[0].params.bed.at("e_gg"), "0.6");
  EXPECT_EQ(d.impacts[0].params.run.at("t_max_s"), "0.2");
  const auto& last = d.impacts.back();
  EXPECT_EQ(last.shape, "triangle");
  EXPECT_EQ(last.vin[0], 4.0);
  EXPECT_NEAR(last.alpha_in_rad, 30.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_EQ(*last.seed, 1);
  EXPECT_EQ(last.params.block.at("mu_gb"), "0.6");
  EXPECT_EQ(last.params.bed.at("E_grain_Pa"), "1e+08");  // common [bed] applies to the design
  std::set<std::string> ids;
  for (const auto& s : d.impacts) EXPECT_TRUE(ids.insert(s.id).second) << s.id;
}

// [design.sample]: a Latin hypercube over grain parameters, crossed with [design.vary]. Each
// sampled axis puts exactly one point in each of its n equal strata (the defining property of a
// Latin hypercube, McKay et al. 1979), the replicas of one point share its bed, and the same seed
// gives the same design.
TEST(Design, LatinHypercubeSampleOfGrainParameters) {
  const std::string text = R"([design]
incident = [[2.9, -2.3, -65.0]]
[design.sample]
n = 8
seed = 3
"bed.mu_gg" = [0.5, 1.0]
"block.mur_gb" = [0.0, 0.6]
[design.vary]
"run.x_impact_frac" = [0.3, 0.36]
)";
  const auto d = read_campaign_design(temp_file("lhs.toml", text), decks());
  ASSERT_EQ(d.impacts.size(), 16u);
  std::set<int> strata_mu, strata_mur;
  std::set<std::string> beds;
  for (std::size_t i = 0; i < d.impacts.size(); i += 2) {
    const auto& a = d.impacts[i];
    const auto& b = d.impacts[i + 1];
    EXPECT_EQ(a.params.bed.at("mu_gg"), b.params.bed.at("mu_gg"));  // replicas of one point
    EXPECT_NE(a.params.run.at("x_impact_frac"), b.params.run.at("x_impact_frac"));
    EXPECT_EQ(bed_key(decks(), bed_overrides(a)), bed_key(decks(), bed_overrides(b)));
    beds.insert(bed_key(decks(), bed_overrides(a)));
    const double mu = std::stod(a.params.bed.at("mu_gg"));
    const double mur = std::stod(a.params.block.at("mur_gb"));
    ASSERT_GE(mu, 0.5);
    ASSERT_LE(mu, 1.0);
    ASSERT_GE(mur, 0.0);
    ASSERT_LE(mur, 0.6);
    strata_mu.insert(static_cast<int>((mu - 0.5) / 0.5 * 8));
    strata_mur.insert(static_cast<int>(mur / 0.6 * 8));
    EXPECT_NE(a.id.find(fmt::format("-p{:02d}", i / 2)), std::string::npos) << a.id;
  }
  EXPECT_EQ(strata_mu.size(), 8u);
  EXPECT_EQ(strata_mur.size(), 8u);
  EXPECT_EQ(beds.size(), 8u);
  const auto again = read_campaign_design(temp_file("lhs2.toml", text), decks());
  for (std::size_t i = 0; i < d.impacts.size(); ++i)
    EXPECT_EQ(spec_json(again.impacts[i]), spec_json(d.impacts[i]));
}

// [design.tie]: a parameter takes a sampled one's value at every point (issue 32, item 2's
// grain-block rolling resistance tied to the grains'); a source that is not varied is refused.
TEST(Design, TiedParameterFollowsTheSampledOne) {
  const auto d = read_campaign_design(temp_file("tie.toml", R"([design]
incident = [[2.9, -2.3, -65.0]]
[design.sample]
n = 4
seed = 5
"bed.mur_gg" = [0.05, 0.7]
[design.tie]
"block.mur_gb" = "bed.mur_gg"
)"),
                                      decks());
  ASSERT_EQ(d.impacts.size(), 4u);
  std::set<std::string> values;
  for (const auto& s : d.impacts) {
    EXPECT_EQ(s.params.block.at("mur_gb"), s.params.bed.at("mur_gg")) << s.id;
    values.insert(s.params.block.at("mur_gb"));
  }
  EXPECT_EQ(values.size(), 4u);
  try {
    (void)read_campaign_design(temp_file("tie-bad.toml", R"([design]
incident = [[2.9, -2.3, -65.0]]
[design.tie]
"block.mur_gb" = "bed.mu_gg"
)"),
                               decks());
    ADD_FAILURE() << "a tie to a parameter the design does not vary was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "design.tie.block.mur_gb");
    EXPECT_EQ(e.line(), 4u);
  }
}

// alpha_in_deg_sample: the lab triangles' unknown orientation, one stratified angle per release.
TEST(Design, OneSampledOrientationPerIncidentState) {
  const auto path = temp_file(
      "tri.toml", "[design]\nshape = \"triangle\"\nincident_from = \"" +
                      std::string(RICOCHET_SOURCE_DIR) +
                      "/data/lab/triangles.csv\"\nalpha_in_deg_sample = { range = [-60.0, 60.0], "
                      "seed = 4 }\n");
  const auto d = read_campaign_design(path, decks());
  ASSERT_EQ(d.impacts.size(), 31u);  // paper Appendix A, triangles
  std::set<int> strata;
  for (const auto& s : d.impacts) {
    const double deg = s.alpha_in_rad * 180.0 / std::numbers::pi;
    ASSERT_GE(deg, -60.0);
    ASSERT_LE(deg, 60.0);
    strata.insert(static_cast<int>((deg + 60.0) / 120.0 * 31));
    EXPECT_EQ(s.id[0], 'T');  // the lab ids, no angle suffix
  }
  EXPECT_EQ(strata.size(), 31u);
}

TEST(Design, IncidentStatesFromTheLabFile) {
  const auto path =
      temp_file("lab.toml", "[design]\nincident_from = \"" + std::string(RICOCHET_SOURCE_DIR) +
                                "/data/lab/cylinders.csv\"\nwhere = \"vin_x<2.8\"\n");
  const auto d = read_campaign_design(path, decks());
  ASSERT_FALSE(d.impacts.empty());
  for (const auto& s : d.impacts) {
    EXPECT_LT(s.vin[0], 2.8);
    EXPECT_EQ(s.id[0], 'C');  // the lab ids
  }
}

// Every campaign file shipped with the decks parses: names, sections and values are valid for
// the decks of this commit (a default change pins the former value in the files that used it).
TEST(Design, EveryShippedCampaignFileParses) {
  const fs::path dir = fs::path(RICOCHET_SOURCE_DIR) / "liggghts-inputs/campaigns";
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".toml") continue;
    ++files;
    EXPECT_NO_THROW({
      const auto d = read_campaign_design(e.path().string(), decks());
      EXPECT_FALSE(d.impacts.empty()) << e.path();
    }) << e.path();
  }
  EXPECT_GE(files, 40u);
}

// Issue 32's stiffness plateau: 7 states x 3 replica beds x 3 grain stiffnesses, one bed per
// stiffness and seed (shared by the cylinder and the triangles), ordered cheap level first and,
// within a level, the cylinder on all three beds before any triangle.
TEST(Design, StiffnessPlateauDesign) {
  const fs::path dir = fs::path(RICOCHET_SOURCE_DIR) / "liggghts-inputs/campaigns";
  const auto d = read_campaign_design((dir / "stiffness-plateau.toml").string(), decks());
  ASSERT_EQ(d.impacts.size(), 63u);
  std::set<std::string> beds;
  std::vector<double> level;
  for (const auto& s : d.impacts) {
    beds.insert(bed_key(decks(), bed_overrides(s)));
    level.push_back(std::stod(s.params.bed.at("E_grain_Pa")));
  }
  EXPECT_EQ(beds.size(), 9u);
  EXPECT_TRUE(std::is_sorted(level.begin(), level.end()));
  for (std::size_t l = 0; l < 3; ++l) {
    for (std::size_t k = 0; k < 21; ++k)
      EXPECT_EQ(d.impacts[21 * l + k].shape, k < 3 ? "cylinder" : "triangle") << l << " " << k;
  }
  EXPECT_EQ(d.impacts[0].id, "E1.5e7-cyl-s0");
  EXPECT_DOUBLE_EQ(d.impacts[0].vin[ricochet::kVx], 2.9);
  EXPECT_EQ(d.impacts[62].id, "E1.5e9-T22-s2");
}

// Its pre-registered consequence (the rule failed at 1.5e9 Pa): the same 63 impacts, identical,
// then the 1.5e10 Pa level on the same states and seeds in the same order, so that the campaign
// file of the first resumes with them done and every 1.5e10 impact pairs with a 1.5e9 one.
TEST(Design, StiffnessPlateauExtensionKeepsTheFirstCampaign) {
  const fs::path dir = fs::path(RICOCHET_SOURCE_DIR) / "liggghts-inputs/campaigns";
  const auto first = read_campaign_design((dir / "stiffness-plateau.toml").string(), decks());
  const auto ext = read_campaign_design((dir / "stiffness-plateau-1.5e10.toml").string(), decks());
  ASSERT_EQ(ext.impacts.size(), 84u);
  EXPECT_EQ(ext.name, first.name);
  for (std::size_t k = 0; k < 63; ++k) {
    EXPECT_EQ(ext.impacts[k].id, first.impacts[k].id);
    EXPECT_EQ(spec_json(ext.impacts[k]), spec_json(first.impacts[k])) << first.impacts[k].id;
  }
  for (std::size_t k = 0; k < 21; ++k) {
    const auto& a = first.impacts[42 + k];  // the 1.5e9 level
    const auto& b = ext.impacts[63 + k];
    EXPECT_EQ(b.id, "E1.5e10-" + a.id.substr(std::string("E1.5e9-").size()));
    EXPECT_DOUBLE_EQ(std::stod(b.params.bed.at("E_grain_Pa")), 1.5e10);
    EXPECT_EQ(b.seed, a.seed);
    EXPECT_EQ(b.vin, a.vin);
    EXPECT_EQ(b.shape, a.shape);
  }
}

// The example designs shipped with the decks are valid and mean what their comments say.
TEST(Design, ShippedCampaignDesigns) {
  const fs::path dir = fs::path(RICOCHET_SOURCE_DIR) / "liggghts-inputs/campaigns";
  const auto lab = read_campaign_design((dir / "lab-cylinders.toml").string(), decks());
  EXPECT_EQ(lab.impacts.size(), 28u);  // paper Appendix A, cylinders
  EXPECT_EQ(lab.impacts.front().id, "C01");
  const auto stiff = read_campaign_design((dir / "grain-stiffness.toml").string(), decks());
  ASSERT_EQ(stiff.impacts.size(), 9u);
  std::set<std::string> keys;
  for (const auto& s : stiff.impacts) keys.insert(bed_key(decks(), bed_overrides(s)));
  EXPECT_EQ(keys.size(), 9u);  // 3 stiffnesses x 3 replica beds
  // Position replicas share one bed (no new bed per replica: the default bed takes 9 minutes).
  for (const char* name : {"speeds.toml", "lab-cylinders-replicas.toml", "main-job.toml"}) {
    const auto d = read_campaign_design((dir / name).string(), decks());
    std::set<std::string> beds;
    for (const auto& s : d.impacts) beds.insert(bed_key(decks(), bed_overrides(s)));
    EXPECT_EQ(beds.size(), 1u) << name;
    EXPECT_EQ(d.impacts.size() % 2, 0u) << name;  // every state at two positions
  }
  EXPECT_EQ(
      read_campaign_design((dir / "lab-cylinders-replicas.toml").string(), decks()).impacts.size(),
      56u);
  // The calibration study's designs (docs/resolved-model.md, "Calibration of the grains").
  EXPECT_EQ(read_campaign_design((dir / "bed-calibration.toml").string(), decks()).impacts.size(),
            144u);  // 48 sampled grain sets x 3 positions
  const auto cal = read_campaign_design((dir / "lab-cylinders-calibrated.toml").string(), decks());
  const auto tri = read_campaign_design((dir / "lab-triangles-blind.toml").string(), decks());
  EXPECT_EQ(cal.impacts.size(), 28u);
  EXPECT_EQ(tri.impacts.size(), 31u);
  // The blind triangles use the calibrated grains and grain-block contact, nothing re-tuned.
  for (const char* k : {"e_gg", "mu_gg", "mu_pour", "mur_gg"})
    EXPECT_EQ(tri.impacts[0].params.bed.at(k), cal.impacts[0].params.bed.at(k)) << k;
  EXPECT_EQ(tri.impacts[0].params.block, cal.impacts[0].params.block);
  const auto conv = read_campaign_design((dir / "convergence.toml").string(), decks());
  ASSERT_EQ(conv.impacts.size(), 27u);  // 9 resolutions x 3 replica beds
  std::set<std::string> conv_beds;
  for (const auto& s : conv.impacts) conv_beds.insert(bed_key(decks(), bed_overrides(s)));
  EXPECT_EQ(conv_beds.size(), 27u);
  // The loop's sets (issue 11 item 5): N impacts, all on the bed and block of `calibrated`.
  auto expect_loop_set = [&](const char* name, std::size_t n, const CampaignDesign& calibrated) {
    const auto d = read_campaign_design((dir / name).string(), decks());
    EXPECT_EQ(d.impacts.size(), n) << name;
    std::set<std::string> beds;
    for (const auto& s : d.impacts) beds.insert(bed_key(decks(), bed_overrides(s)));
    EXPECT_EQ(beds, std::set<std::string>{bed_key(decks(), bed_overrides(calibrated.impacts[0]))})
        << name;
    EXPECT_EQ(d.impacts[0].params.block, calibrated.impacts[0].params.block) << name;
  };
  expect_loop_set("speeds-calibrated.toml", 27, cal);
  expect_loop_set("lab-cylinders-calibrated-replicas.toml", 84, cal);
  // The second calibration: two designs on the 1.0 m slab, the real check of its optimum and the
  // blind triangles on that bed, which differ from the first blind run by the bed only.
  EXPECT_EQ(
      read_campaign_design((dir / "bed-calibration-long.toml").string(), decks()).impacts.size(),
      60u);  // 30 sampled grain sets x 2 positions
  EXPECT_EQ(
      read_campaign_design((dir / "bed-calibration-refine.toml").string(), decks()).impacts.size(),
      48u);  // 24 x 2
  EXPECT_EQ(
      read_campaign_design((dir / "bed-probe-stiffness.toml").string(), decks()).impacts.size(),
      24u);  // 3 stiffnesses x 2 restitutions x 2 frictions x 2 positions
  const auto cal2 =
      read_campaign_design((dir / "lab-cylinders-calibrated-long.toml").string(), decks());
  const auto tri2 = read_campaign_design((dir / "lab-triangles-blind-long.toml").string(), decks());
  EXPECT_EQ(cal2.impacts.size(), 28u);
  ASSERT_EQ(tri2.impacts.size(), 31u);
  EXPECT_EQ(bed_key(decks(), bed_overrides(tri2.impacts[0])),
            bed_key(decks(), bed_overrides(cal2.impacts[0])));
  EXPECT_EQ(tri2.impacts[0].params.block, cal2.impacts[0].params.block);
  EXPECT_EQ(read_campaign_design((dir / "bed-probe-rolling.toml").string(), decks()).impacts.size(),
            8u);  // 4 grain-block rolling frictions x 2 positions
  const auto rolling_model =
      read_campaign_design((dir / "bed-probe-rolling-model.toml").string(), decks());
  ASSERT_EQ(rolling_model.impacts.size(), 6u);  // 3 grain rolling frictions x 2 positions
  EXPECT_EQ(rolling_model.impacts[0].params.bed.at("rolling_model"), "cdt");
  const auto cal4 = read_campaign_design((dir / "bed-calibration-cdt.toml").string(), decks());
  ASSERT_EQ(cal4.impacts.size(), 80u);  // 40 Latin-hypercube sets x 2 positions
  EXPECT_EQ(cal4.impacts[0].params.bed.at("rolling_model"), "cdt");
  EXPECT_EQ(read_campaign_design((dir / "bed-probe-depth.toml").string(), decks()).impacts.size(),
            6u);  // 3 depths x 2 positions
  const auto deep =
      read_campaign_design((dir / "lab-cylinders-calibrated-long-deep.toml").string(), decks());
  ASSERT_EQ(deep.impacts.size(), 28u);
  EXPECT_EQ(deep.impacts[0].params.bed.at("H_m"), "0.1");  // the one change from the second bed
  EXPECT_EQ(deep.impacts[0].params.block, cal2.impacts[0].params.block);
  // The loop's sets on the second bed.
  expect_loop_set("speeds-calibrated-long.toml", 27, cal2);
  expect_loop_set("lab-cylinders-calibrated-long-replicas.toml", 84, cal2);
  for (std::size_t k = 0; k < tri.impacts.size(); ++k) {
    EXPECT_EQ(tri2.impacts[k].id, tri.impacts[k].id);
    EXPECT_EQ(tri2.impacts[k].alpha_in_rad, tri.impacts[k].alpha_in_rad) << tri.impacts[k].id;
  }
  // The third calibration (cdt): the real check at the optimum, the loop's speeds set and the
  // blind triangles on that one bed; the blind triangles keep the first blind run's orientations,
  // so that the three blind predictions differ by the bed only.
  const auto cal3 = read_campaign_design((dir / "lab-cylinders-cdt.toml").string(), decks());
  ASSERT_EQ(cal3.impacts.size(), 84u);  // 28 lab states x 3 positions
  EXPECT_EQ(cal3.impacts[0].params.bed.at("rolling_model"), "cdt");
  expect_loop_set("speeds-cdt.toml", 27, cal3);
  expect_loop_set("lab-triangles-blind-cdt.toml", 31, cal3);
  const auto tri3 = read_campaign_design((dir / "lab-triangles-blind-cdt.toml").string(), decks());
  for (std::size_t k = 0; k < tri.impacts.size(); ++k)
    EXPECT_EQ(tri3.impacts[k].alpha_in_rad, tri.impacts[k].alpha_in_rad) << tri.impacts[k].id;
  // The fifth calibration (the decks' default bed): the real check at the lab's 28 states, the
  // blind triangles and the loop's speeds set on that one bed (built once, then cached), the
  // triangles with the orientations of the fourth bed's blind run, release by release.
  const auto cal5 =
      read_campaign_design((dir / "lab-cylinders-rolling-gb-ground.toml").string(), decks());
  ASSERT_EQ(cal5.impacts.size(), 28u);
  expect_loop_set("lab-triangles-blind-rolling-gb.toml", 31, cal5);
  expect_loop_set("speeds-rolling-gb.toml", 27, cal5);
  const auto tri4 =
      read_campaign_design((dir / "lab-triangles-blind-default-calibrated.toml").string(), decks());
  const auto tri5 =
      read_campaign_design((dir / "lab-triangles-blind-rolling-gb.toml").string(), decks());
  ASSERT_EQ(tri4.impacts.size(), tri5.impacts.size());
  for (std::size_t k = 0; k < tri4.impacts.size(); ++k)
    EXPECT_EQ(tri5.impacts[k].alpha_in_rad, tri4.impacts[k].alpha_in_rad) << tri4.impacts[k].id;
  const auto resolution =
      read_campaign_design((dir / "bed-probe-resolution-cdt.toml").string(), decks());
  ASSERT_EQ(resolution.impacts.size(), 8u);  // {1, 0.75} x grains {0.06, 0.10} m deep x 2
  EXPECT_EQ(bed_key(decks(), bed_overrides(resolution.impacts[0])),
            bed_key(decks(), bed_overrides(cal3.impacts[0])));  // the base is the checked bed
  EXPECT_EQ(
      read_campaign_design((dir / "bed-probe-width-cdt.toml").string(), decks()).impacts.size(),
      4u);  // 2 widths x 2 positions
  // Packing from release to release: the fifth check's 28 states, grains and block, each
  // release on one of 7 beds whose pouring friction steps 0.18-0.38 (release k on level k mod 7);
  // everything else as the fifth check (its bed is level 3 but for the seed).
  const auto packing =
      read_campaign_design((dir / "lab-cylinders-packing-scatter.toml").string(), decks());
  ASSERT_EQ(packing.impacts.size(), 28u);
  std::set<std::string> packing_beds;
  for (std::size_t k = 0; k < 28; ++k) {
    const auto& s = packing.impacts[k];
    packing_beds.insert(bed_key(decks(), bed_overrides(s)));
    EXPECT_EQ(s.id, cal5.impacts[k].id.substr(0, s.id.size()));
    EXPECT_EQ(s.vin, cal5.impacts[k].vin) << s.id;
    EXPECT_NEAR(std::stod(s.params.bed.at("mu_pour")), 0.18 + 0.2 / 6 * static_cast<double>(k % 7),
                1e-3)
        << s.id;
    EXPECT_EQ(s.params.block, cal5.impacts[k].params.block) << s.id;
    for (const char* b : {"E_grain_Pa", "mur_gg"})
      EXPECT_EQ(std::stod(s.params.bed.at(b)), std::stod(cal5.impacts[k].params.bed.at(b))) << b;
  }
  EXPECT_EQ(packing_beds.size(), 7u);
  // The triangles' grain-size check: six of the fifth bed's blind releases, release by release
  // (state, orientation to 1e-12 rad, position, grain law, block), on grains 0.75x.
  const auto fine =
      read_campaign_design((dir / "lab-triangles-fine-grains.toml").string(), decks());
  auto default_param = [](const std::string& name) {
    for (const auto& p : decks().bed_params)
      if (p.name == name) return p.default_value;
    ADD_FAILURE() << "no bed parameter " << name;
    return std::string("nan");
  };
  ASSERT_EQ(fine.impacts.size(), 6u);
  for (std::size_t k = 0; k < fine.impacts.size(); ++k) {
    const auto& s = fine.impacts[k];
    EXPECT_EQ(s.id, fmt::format("T{:02d}", 2 + 4 * k));
    const auto& base = tri5.impacts[1 + 4 * k];
    EXPECT_EQ(base.id, s.id);
    EXPECT_EQ(s.vin, base.vin) << s.id;
    EXPECT_NEAR(s.alpha_in_rad, base.alpha_in_rad, 1e-12) << s.id;
    EXPECT_EQ(s.params.block, base.params.block) << s.id;
    EXPECT_EQ(s.params.run, base.params.run) << s.id;
    auto bed = s.params.bed;
    for (const char* r : {"r1_m", "r2_m", "r3_m"}) {
      EXPECT_NEAR(std::stod(bed.at(r)), 0.75 * std::stod(default_param(r)), 1e-12) << r;
      bed.erase(r);
    }
    EXPECT_EQ(bed, base.params.bed) << s.id;
  }
}

void expect_error(const std::string& text, std::size_t line, const std::string& field) {
  const auto path = temp_file("bad.toml", text);
  try {
    read_campaign_design(path, decks());
    FAIL() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

// [campaign] end_wall_rerun_Lx_m: the impacts the file records at an end wall, and only those,
// come back on the longer bed, landing at the same distance from the back wall (x_impact_frac
// times Lx, in metres, unchanged), with their grain parameters (a sampled point keeps its
// values, so calibrate-grains groups the rerun with it); a bed already that long is not rerun.
TEST(Design, EndWallImpactsAreRerunOnALongerBedAtTheSameLandingPoint) {
  const auto path = temp_file("end-wall.toml", R"(
[campaign]
end_wall_rerun_Lx_m = 1.5
[bed]
Lx_m = 1.0
[[impact]]
id = "long"
vin = [2.9, -2.3, -65.0]
bed = { Lx_m = 1.5 }
[design]
incident = [[2.9, -2.3, -65.0]]
id_prefix = "p"
[design.vary]
"run.x_impact_frac" = [0.26, 0.32]
"bed.mu_gg" = [0.4, 0.8]
)");
  const auto d = read_campaign_design(path, decks());
  EXPECT_EQ(d.end_wall_rerun_Lx_m, 1.5);
  ASSERT_EQ(d.impacts.size(), 5u);
  auto entry = [](const std::string& id, const std::string& status) {
    CampaignEntry e;
    e.id = id;
    e.status = status;
    return e;
  };
  // Nothing at a wall yet: no rerun.
  EXPECT_TRUE(end_wall_reruns(d, decks(), {entry(d.impacts[1].id, "rebound")}).empty());
  const std::vector<CampaignEntry> index = {
      entry("long", "end_wall"), entry(d.impacts[1].id, "rebound"),
      entry(d.impacts[4].id, "end_wall"), entry(d.impacts[2].id, "no_rebound")};
  const auto reruns = end_wall_reruns(d, decks(), index);
  ASSERT_EQ(reruns.size(), 1u);  // "long" is on a 1.5 m bed already
  const ImpactSpec& was = d.impacts[4];
  const ImpactSpec& r = reruns[0];
  EXPECT_EQ(r.id, was.id + "-Lx1.5");
  EXPECT_EQ(r.params.bed.at("Lx_m"), "1.5");
  EXPECT_EQ(r.params.bed.at("mu_gg"), was.params.bed.at("mu_gg"));
  EXPECT_NEAR(std::stod(r.params.run.at("x_impact_frac")) * 1.5,
              std::stod(was.params.run.at("x_impact_frac")) * 1.0, 1e-12);
  EXPECT_EQ(r.vin, was.vin);
  EXPECT_EQ(r.seed, was.seed);
  EXPECT_NE(bed_key(decks(), bed_overrides(r)), bed_key(decks(), bed_overrides(was)));
  // The dry run reads the file's index and lists the rerun after the design's impacts, still to
  // run; without the key there is none.
  const std::string file = temp_file("end-wall.h5", "");
  fs::remove(file);
  for (const auto& e : index) {
    ImpactResult res;
    res.id = e.id;
    res.status = e.status;
    const auto it = std::find_if(d.impacts.begin(), d.impacts.end(),
                                 [&](const ImpactSpec& s) { return s.id == e.id; });
    res.impact.id = e.id;
    res.impact.shape = it->shape;
    res.impact.vin = it->vin;
    res.impact.vout = {1.0, 0.5, -10.0};
    append_result(file, res, *it, "end-wall-test");
  }
  const auto plan = plan_campaign(d, decks(), file);
  ASSERT_EQ(plan.size(), 6u);
  EXPECT_EQ(plan[4].status, "end_wall");
  EXPECT_EQ(plan[5].id, r.id);
  EXPECT_TRUE(plan[5].status.empty());
  CampaignDesign off = d;
  off.end_wall_rerun_Lx_m = 0;
  EXPECT_TRUE(end_wall_reruns(off, decks(), index).empty());
  EXPECT_EQ(plan_campaign(off, decks(), file).size(), 5u);
}

TEST(Design, ErrorsNameFileLineAndKey) {
  expect_error(
      "[design]\nincident = [[2.9, -2.3, -65.0]]\n[design.sample]\nn = 4\n\"bed.mu_gg\" = [1.0, "
      "0.5]\n",
      5, "design.sample.bed.mu_gg");
  expect_error(
      "[design]\nincident = [[2.9, -2.3, -65.0]]\n[design.sample]\nn = 1\n\"bed.mu_gg\" = [0.5, "
      "1.0]\n",
      4, "design.sample.n");
  expect_error(
      "[design]\nincident = [[2.9, -2.3, -65.0]]\n[design.sample]\nn = 4\n\"run.t_max_s\" = [0.1, "
      "0.2]\n",
      5, "design.sample.run.t_max_s");
  expect_error("[campaign]\nnmae = \"x\"\n", 2, "campaign.nmae");
  expect_error("[campaign]\nend_wall_rerun_Lx_m = -1.5\n", 2, "campaign.end_wall_rerun_Lx_m");
  expect_error("[[impact]]\nid = \"a\"\nvin = [2.9, -2.3]\n", 3, "impact[0].vin");
  expect_error("[[impact]]\nid = \"a\"\nvin = [2.9, 2.3, -65]\n", 3, "impact[0].vin");
  expect_error("[bed]\nE_grain_Pa = \"soft\"\n", 2, "bed.E_grain_Pa");
  expect_error("[[impact]]\nvin = [2.9, -2.3, -65]\nshape = \"hexagon\"\n", 3, "impact[0].shape");
  expect_error(
      "[[impact]]\nid = \"a\"\nvin = [2.9, -2.3, -65]\n[[impact]]\nid = \"a\"\nvin = [2.9, -2.3, "
      "-65]\n",
      4, "impact[1].id");
  expect_error(
      "[design]\nincident = [[2.9, -2.3, -65]]\n[design.vary]\n\"bed.e_gg\" = [0.3, 2.0]\n", 4,
      "bed.e_gg");
  expect_error("[campaign]\nname = \"empty\"\n", 0, "impact");
}

// Found with fuzz/fuzz_campaign_toml's property checks: nan and inf were accepted as velocities,
// angles and frame rates, an angle of 1e308 degrees overflowed to an infinite angle in radians,
// n = 100000000 samples exhausted memory (or time) while the design was expanded, and an error in
// `where` named "--where" instead of the design file.
TEST(Design, NonFiniteNumbersHugeDesignsAndBadFiltersAreLocatedErrors) {
  expect_error("[[impact]]\nvin = [nan, -2.3, 0]\n", 2, "impact[0].vin");
  expect_error("[[impact]]\nvin = [1, -2.3, 0]\nalpha_in_deg = inf\n", 3, "impact[0].alpha_in_deg");
  expect_error("[[impact]]\nvin = [1, -2.3, 0]\nalpha_in_deg = 1e308\n", 3,
               "impact[0].alpha_in_deg");
  expect_error("[extract]\nfps = inf\n[[impact]]\nvin = [1, -2.3, 0]\n", 2, "extract.fps");
  expect_error("[design]\nincident = [[1, -2, 0]]\nalpha_in_deg = [0, 1e308]\n", 3,
               "design.alpha_in_deg");
  expect_error(
      "[design]\nincident = [[1, -2, 0]]\nalpha_in_deg_sample = { range = [-1e308, 1e308] }\n", 3,
      "design.alpha_in_deg_sample.range");
  expect_error(
      "[design]\nincident = [[1, -2, 0]]\n[design.sample]\nn = 100000000\n"
      "\"bed.E_grain_Pa\" = [1e8, 4e8]\n",
      4, "design.sample.n");
  expect_error(
      "[design]\nincident = [[1, -2, 0], [2, -3, 0]]\nseeds = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]\n"
      "[design.vary]\n"
      "\"run.x_impact_frac\" = [0.30, 0.31, 0.32, 0.33, 0.34, 0.35, 0.36, 0.37, 0.38, 0.39]\n"
      "\"block.mu_gb\" = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]\n"
      "\"block.e_gb\" = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]\n",
      1, "design");
  expect_error("[design]\nincident_from = \"" + std::string(RICOCHET_SOURCE_DIR) +
                   "/data/lab/cylinders.csv\"\nwhere = \"vin_x<<3\"\n",
               3, "design.where");
}

}  // namespace
