// Calibration of grain parameters through a kriging surrogate, without LIGGGHTS: a campaign file
// whose "resolved" rebounds follow known smooth laws of two grain parameters (tanh and
// quadratic shapes, not the Matern kriging's own), with replica scatter, and a third parameter
// that does nothing. The surrogate must validate (leave-one-out Q2), its Sobol indices must
// single out the parameters that act, and the calibration must find the parameters that produce
// the target's mean rebound.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "bed.hpp"
#include "campaign.hpp"
#include "common/error.hpp"
#include "dem_support.hpp"
#include "fit/design.hpp"
#include "grain_calibration.hpp"
#include "support/temp_dir_test.hpp"
#include "synthetic_campaign.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::dem;
namespace fs = std::filesystem;
using dem::test::decks;
using dem::test::kReplicaScatter;
using dem::test::make_campaign;
using dem::test::target_set;

// Each test writes its campaign into a fresh directory of its own (support/temp_dir_test.hpp).
class GrainCalibration : public ricochet::test::TempDirTest {
 protected:
  GrainCalibration() : TempDirTest("dem-grains") {}
};

TEST_F(GrainCalibration, SurrogateValidatesRanksParametersAndFindsTheTarget) {
  const std::string path = make_campaign(dir_, 24);
  GrainCalibrationOptions o;
  o.sobol_n = 5000;
  o.search_n = 8000;
  const auto r = calibrate_grains(path, decks(), target_set(), o);
  ASSERT_EQ(r.parameters, (std::vector<std::string>{"bed.e_gg", "bed.mu_gg", "block.mur_gb"}));
  ASSERT_EQ(r.points.size(), 24u);
  for (const auto& p : r.points) EXPECT_EQ(p.replicas, 3u);
  // Pooled replica scatter: offsets -s, 0, +s have a standard deviation of s.
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(r.replicate_sd[c], kReplicaScatter[c], 1e-3 * kReplicaScatter[c] + 1e-4);
  for (int c = 0; c < 3; ++c) EXPECT_GT(r.q2[c], 0.9) << c;
  // Sobol: V_out^x is mu_gg's, omega_out is mur_gb's, e_gg is inert everywhere.
  EXPECT_GT(r.total[0][1], 0.85);
  EXPECT_LT(r.total[0][2], 0.1);
  EXPECT_GT(r.total[2][2], 0.85);
  for (int c = 0; c < 3; ++c) EXPECT_LT(r.total[c][0], 0.05) << c;
  // The calibrated point reproduces the target's mean and finds the acting parameters.
  EXPECT_NEAR(r.best[1], 0.78, 0.05);
  EXPECT_NEAR(r.best[2], 0.30, 0.05);
  for (int c = 0; c < 3; ++c)
    EXPECT_LT(std::abs(r.best_mean[c] - r.target_mean[c]), 0.5 * r.target_sd[c]) << c;
  EXPECT_GT(r.acceptable_fraction, 0.0);
  EXPECT_LT(r.acceptable_fraction, 0.2);  // e_gg is free, the two others are pinned
}

// The same campaign, target and seed give the same calibration bit for bit (OpenTURNS's
// threaded kriging evaluations once made the last digits vary from run to run).
TEST_F(GrainCalibration, ASeedGivesTheSameCalibrationBitForBit) {
  const std::string path = make_campaign(dir_, 24);
  GrainCalibrationOptions o;
  o.sobol_n = 2000;
  o.search_n = 4000;
  const auto a = calibrate_grains(path, decks(), target_set(), o);
  const auto b = calibrate_grains(path, decks(), target_set(), o);
  EXPECT_EQ(a.q2, b.q2);
  EXPECT_EQ(a.rmse_loo, b.rmse_loo);
  EXPECT_EQ(a.best, b.best);
  EXPECT_EQ(a.best_mean, b.best_mean);
  EXPECT_EQ(a.best_sd, b.best_sd);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(a.total[c], b.total[c]) << c;
  for (std::size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i].loo, b.points[i].loo);
}

TEST_F(GrainCalibration, TooFewDesignPointsIsAnErrorNamingTheFile) {
  const std::string path = make_campaign(dir_, 4);
  try {
    calibrate_grains(path, decks(), target_set(), {});
    FAIL() << "4 points for 3 parameters accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find("need at least 5"), std::string::npos) << e.what();
  }
}

// A band needs each bed's packing: this synthetic campaign records none and has no cache given,
// so the first bed is named, with the three ways to get its packing.
TEST_F(GrainCalibration, ASolidFractionBandNeedsEachBedsPackingAndAnOrderedRange) {
  const std::string path = make_campaign(dir_, 8);
  GrainCalibrationOptions o;
  o.solid_fraction = {0.56, 0.62};
  try {
    calibrate_grains(path, decks(), target_set(), o);
    FAIL() << "a band without any bed's packing accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    const std::string what = e.what();
    for (const char* way : {"no --bed-cache given", "--record-beds", "--packing-from-grain-count"})
      EXPECT_NE(what.find(way), std::string::npos) << what;
  }
  o.bed_cache = dir_.string();
  o.solid_fraction = {0.62, 0.56};
  EXPECT_THROW(calibrate_grains(path, decks(), target_set(), o), InputError);
}

// The beds of a campaign spread over sessions are seldom all in one cache (a new machine loses
// them): calibrate-grains takes each point's solid fraction from the file's record (/dem/beds,
// record_bed_packing) and needs the cache only for a bed the file does not record, naming the
// command that records it.
TEST_F(GrainCalibration, SolidFractionsComeFromTheFileWhenTheCacheLacksTheBeds) {
  const auto key_of = [](double mu, double mur, double) {
    return fmt::format("k{:.4g}-{:.4g}", mu, mur);
  };
  const std::string path = make_campaign(dir_, 8, key_of);
  // A made-up packing law of the points: looser with more grain friction.
  std::map<std::string, double> phi;
  for (const auto& e : read_campaign_index(path)) {
    if (phi.count(e.bed_key)) continue;
    const double mu = std::stod(e.bed_key.substr(1, e.bed_key.find('-') - 1));
    phi[e.bed_key] = 0.64 - 0.08 * mu;
  }
  const std::string empty_cache = (dir_ / "no-beds").string();
  fs::create_directories(empty_cache);
  GrainCalibrationOptions o;
  o.bed_cache = empty_cache;
  o.solid_fraction = {0.56, 0.62};
  o.sobol_n = 2000;
  o.search_n = 2000;
  // One bed unrecorded: an error naming the file, the bed and the remedy.
  auto it = phi.begin();
  for (auto k = std::next(it); k != phi.end(); ++k) {
    BedPacking p;
    p.solid_fraction = k->second;
    record_bed_packing(path, k->first, p);
  }
  try {
    calibrate_grains(path, decks(), target_set(), o);
    FAIL() << "an unrecorded bed outside the cache was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(it->first), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--record-beds"), std::string::npos) << e.what();
  }
  BedPacking p;
  p.solid_fraction = it->second;
  record_bed_packing(path, it->first, p);
  EXPECT_EQ(read_bed_packings(path).size(), phi.size());
  const auto r = calibrate_grains(path, decks(), target_set(), o);
  ASSERT_EQ(r.points.size(), 8u);
  for (const auto& pt : r.points) {
    EXPECT_TRUE(std::isfinite(pt.solid_fraction));
    bool found = false;
    for (const auto& [k, v] : phi) found = found || v == pt.solid_fraction;
    EXPECT_TRUE(found) << pt.solid_fraction;
  }
  // A file that records every bed needs no cache at all: the same points and optimum.
  o.bed_cache.clear();
  const auto no_cache = calibrate_grains(path, decks(), target_set(), o);
  ASSERT_EQ(no_cache.points.size(), r.points.size());
  for (std::size_t i = 0; i < r.points.size(); ++i)
    EXPECT_EQ(no_cache.points[i].solid_fraction, r.points[i].solid_fraction);
  EXPECT_EQ(no_cache.best, r.best);
}

// A new machine has lost the cache of beds built before the file recorded packings: with
// --packing-from-grain-count such a bed's solid fraction is N vbar / V_bed, the factor from the
// recorded beds of the same geometry. The made-up beds below vary that factor by +-0.1 % (the
// spread of the sand calibration's three recorded 1.0 m beds: 0.06 % in V_bed, 0.04 % in vbar),
// so the estimate is off by at most about 0.1 % of phi and its leave-one-out check says so.
TEST_F(GrainCalibration, AnUnrecordedBedIsEstimatedFromItsGrainCountWhenAsked) {
  const auto key_of = [](double mu, double mur, double) {
    return fmt::format("k{:.4g}-{:.4g}", mu, mur);
  };
  const auto phi_of = [](double mu) { return 0.64 - 0.08 * mu; };
  const double vbar_m3 = 1.9056e-7, bed_m3 = 0.0198;
  const auto grains_of = [&](double mu, double, double) {
    return std::lround(phi_of(mu) * bed_m3 / vbar_m3);
  };
  const std::string path = make_campaign(dir_, 8, key_of, grains_of);
  std::map<std::string, BedPacking> beds;
  for (const auto& e : read_campaign_index(path)) {
    if (beds.count(e.bed_key)) continue;
    const double mu = std::stod(e.bed_key.substr(1, e.bed_key.find('-') - 1));
    BedPacking p;
    p.grains = grains_of(mu, 0, 0);
    // The reference's own bed volume, 0.1 % up or down by bed: the estimate cannot be exact.
    p.bed_volume_m3 = bed_m3 * (beds.size() % 2 == 0 ? 1.001 : 0.999);
    p.grain_volume_m3 = static_cast<double>(p.grains) * vbar_m3;
    p.solid_fraction = p.grain_volume_m3 / p.bed_volume_m3;
    beds[e.bed_key] = p;
  }
  const std::string missing = beds.begin()->first;
  for (const auto& [key, p] : beds)
    if (key != missing) record_bed_packing(path, key, p);
  const std::string empty_cache = (dir_ / "no-beds").string();
  fs::create_directories(empty_cache);
  GrainCalibrationOptions o;
  o.bed_cache = empty_cache;
  o.sobol_n = 2000;
  o.search_n = 2000;
  try {
    calibrate_grains(path, decks(), target_set(), o);
    FAIL() << "an unrecorded bed was estimated without being asked";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--packing-from-grain-count"), std::string::npos)
        << e.what();
  }
  o.packing_from_grain_count = true;
  const auto r = calibrate_grains(path, decks(), target_set(), o);
  ASSERT_EQ(r.grain_count_estimates.size(), 1u);
  const GrainCountEstimate& est = r.grain_count_estimates[0];
  EXPECT_EQ(est.beds, std::vector<std::string>{missing});
  EXPECT_EQ(est.references, beds.size() - 1);
  // The leave-one-out error: a reference whose volume is 0.2 % off the others' mean.
  EXPECT_GT(est.loo_max_abs, 0.0005 * 0.56);
  EXPECT_LT(est.loo_max_abs, 0.0025 * 0.62);
  // The geometry is every bed.* value that is not a surrogate input: e_gg and mu_gg are inputs.
  EXPECT_EQ(est.geometry.find("bed.mu_gg"), std::string::npos) << est.geometry;
  EXPECT_NE(est.geometry.find("bed.Lx_m="), std::string::npos) << est.geometry;
  std::size_t estimated = 0;
  for (const auto& pt : r.points) {
    const std::string key = key_of(pt.x[1], pt.x[2], 0);
    if (pt.solid_fraction_source == "grain count") {
      ++estimated;
      EXPECT_EQ(key, missing);
      EXPECT_NEAR(pt.solid_fraction, beds[missing].solid_fraction,
                  0.0015 * beds[missing].solid_fraction);
      EXPECT_NE(pt.solid_fraction, beds[missing].solid_fraction);
    } else {
      EXPECT_EQ(pt.solid_fraction_source, "recorded");
      EXPECT_EQ(pt.solid_fraction, beds[key].solid_fraction);
    }
  }
  EXPECT_EQ(estimated, 1u);
}

TEST(GrainCountPackingEstimate, IsTheReferencesMeanFactorAndChecksItselfLeavingOneOut) {
  std::vector<BedPacking> refs(3);
  const double f[3] = {1.00e-5, 1.01e-5, 0.99e-5};
  const long n[3] = {60000, 59000, 61000};
  for (int i = 0; i < 3; ++i) {
    refs[i].grains = n[i];
    refs[i].bed_volume_m3 = 0.02;
    refs[i].grain_volume_m3 = f[i] * 0.02 * static_cast<double>(n[i]);
    refs[i].solid_fraction = refs[i].grain_volume_m3 / refs[i].bed_volume_m3;
  }
  const GrainCountPacking g = grain_count_packing(refs);
  EXPECT_EQ(g.references, 3u);
  EXPECT_NEAR(g.per_grain, 1.0e-5, 1e-15);
  EXPECT_NEAR(g.solid_fraction(58000), 0.58, 1e-9);
  // Left out, the second's factor is 0.015e-5 above the others' mean 0.995e-5 (59000 grains:
  // 0.00885 off), the third's 0.015e-5 below 1.005e-5 (61000: 0.00915), the first's on 1.0e-5.
  EXPECT_NEAR(g.loo_max_abs, 0.00915, 1e-9);
  EXPECT_TRUE(std::isnan(grain_count_packing({refs[0]}).loo_max_abs));
  EXPECT_THROW(grain_count_packing({}), std::invalid_argument);
  refs[1].grains = 0;
  EXPECT_THROW(grain_count_packing(refs), std::invalid_argument);
}

}  // namespace
