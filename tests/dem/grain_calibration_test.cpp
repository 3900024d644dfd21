// Calibration of grain parameters through a kriging surrogate, without LIGGGHTS: a campaign file
// whose "resolved" rebounds follow known smooth laws of two grain parameters (tanh and
// quadratic shapes, not the Matern kriging's own), with replica scatter, and a third parameter
// that does nothing. The surrogate must validate (leave-one-out Q2), its Sobol indices must
// single out the parameters that act, and the calibration must find the parameters that produce
// the target's mean rebound.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "campaign.hpp"
#include "common/error.hpp"
#include "dem_support.hpp"
#include "fit/design.hpp"
#include "grain_calibration.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::dem;
namespace fs = std::filesystem;
using test::decks;

// The synthetic bed's response (m/s, m/s, rad/s): mu_gg sets V_out^x (a tanh step, as the
// rebound-to-ploughing change of docs/resolved-model.md), mur_gb the spin and V_out^y, e_gg
// nothing.
Vel3 response(double mu_gg, double mur_gb) {
  return {3.0 + 0.6 * std::tanh(3.0 * (mu_gg - 0.7)), 0.95 - 0.8 * mur_gb * mur_gb + 0.2 * mu_gg,
          -52.0 + 25.0 * mur_gb};
}

const Vel3 kReplicaScatter = {0.03, 0.03, 0.8};  // replica offsets (m/s, m/s, rad/s)

std::string make_campaign(const fs::path& dir, std::size_t points) {
  const std::string path = (dir / "campaign.h5").string();
  const auto u = fit::lhs_unit_design(3, points, 7);
  for (std::size_t p = 0; p < points; ++p) {
    const double mu = 0.5 + 0.5 * u[3 * p], mur = 0.6 * u[3 * p + 1], e = 0.4 + 0.5 * u[3 * p + 2];
    for (int rep = 0; rep < 3; ++rep) {
      ImpactSpec spec;
      spec.id = fmt::format("p{:02d}-r{}", p, rep);
      spec.vin = {2.9, -2.3, -65.0};
      spec.params.bed["mu_gg"] = fmt::format("{:.4g}", mu);
      spec.params.bed["e_gg"] = fmt::format("{:.4g}", e);
      spec.params.block["mur_gb"] = fmt::format("{:.4g}", mur);
      spec.params.run["x_impact_frac"] = fmt::format("{}", 0.28 + 0.06 * rep);
      ImpactResult r;
      r.id = spec.id;
      r.status = "rebound";
      r.impact.id = spec.id;
      r.impact.shape = "cylinder";
      r.impact.vin = spec.vin;
      r.impact.vout =
          response(std::stod(spec.params.bed["mu_gg"]), std::stod(spec.params.block["mur_gb"]));
      for (int c = 0; c < 3; ++c) r.impact.vout[c] += (rep - 1) * kReplicaScatter[c];
      r.impact.extra.assign(impact_extra_names().size(), 0.0);
      append_result(path, r, spec, "synthetic");
    }
  }
  return path;
}

// A target whose mean is the response at (mu_gg, mur_gb) = (0.78, 0.30), scatter about a tenth of
// the lab's so that the calibrated point is sharply defined.
ImpactSet target_set() {
  ImpactSet t;
  const Vel3 m = response(0.78, 0.30);
  for (int i = 0; i < 20; ++i) {
    Impact im;
    im.id = fmt::format("L{}", i);
    im.shape = "cylinder";
    im.vin = {2.9, -2.3, -65.0};
    const double s = (i % 2 == 0 ? 1.0 : -1.0) * (1 + i / 2 % 3);
    im.vout = {m[0] + 0.02 * s, m[1] + 0.02 * s, m[2] + 0.7 * s};
    t.impacts.push_back(im);
  }
  return t;
}

TEST(GrainCalibration, SurrogateValidatesRanksParametersAndFindsTheTarget) {
  const fs::path dir = fs::temp_directory_path() / ("dem-grains-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = make_campaign(dir, 24);
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
  fs::remove_all(dir);
}

TEST(GrainCalibration, TooFewDesignPointsIsAnErrorNamingTheFile) {
  const fs::path dir = fs::temp_directory_path() / ("dem-grains-few-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = make_campaign(dir, 4);
  try {
    calibrate_grains(path, decks(), target_set(), {});
    FAIL() << "4 points for 3 parameters accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find("need at least 5"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
