// A synthetic [design.sample] campaign for the grain-calibration tests (no LIGGGHTS run): its
// "resolved" rebounds follow known smooth laws of two grain parameters (tanh and quadratic shapes,
// not the Matern kriging's own), with replica scatter, and a third parameter that does nothing.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

#include "campaign.hpp"
#include "campaign_store.hpp"
#include "fit/design.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::dem::test {

// The synthetic bed's response (m/s, m/s, rad/s): mu_gg sets V_out^x (a tanh step, as the
// rebound-to-ploughing change of docs/resolved-model.md), mur_gb the spin and V_out^y, e_gg
// nothing.
inline Vel3 response(double mu_gg, double mur_gb) {
  return {3.0 + 0.6 * std::tanh(3.0 * (mu_gg - 0.7)), 0.95 - 0.8 * mur_gb * mur_gb + 0.2 * mu_gg,
          -52.0 + 25.0 * mur_gb};
}

inline const Vel3 kReplicaScatter = {0.03, 0.03, 0.8};  // replica offsets (m/s, m/s, rad/s)

/// Bed key of a design point (mu_gg, mur_gb, e_gg) in the campaign's index; empty: none.
using BedKeyOf = std::function<std::string(double mu_gg, double mur_gb, double e_gg)>;

/// Grain count of a design point's bed (the index's "grains"); empty: 0.
using GrainsOf = std::function<long(double mu_gg, double mur_gb, double e_gg)>;

/// Status of a design point's impacts (e.g. "timeout" where its block never leaves the bed);
/// empty: every impact rebounds.
using StatusOf = std::function<std::string(double mu_gg, double mur_gb, double e_gg)>;

inline std::string make_campaign(const std::filesystem::path& dir, std::size_t points,
                                 const BedKeyOf& bed_key = {}, const GrainsOf& grains = {},
                                 const StatusOf& status = {}) {
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
      r.status = status ? status(mu, mur, e) : "rebound";
      r.impact.id = spec.id;
      r.impact.shape = "cylinder";
      r.impact.vin = spec.vin;
      r.impact.vout =
          response(std::stod(spec.params.bed["mu_gg"]), std::stod(spec.params.block["mur_gb"]));
      for (int c = 0; c < 3; ++c) r.impact.vout[c] += (rep - 1) * kReplicaScatter[c];
      r.impact.extra.assign(impact_extra_names().size(), 0.0);
      if (bed_key) r.bed_key = bed_key(mu, mur, e);
      if (grains) r.grains = grains(mu, mur, e);
      append_result(path, r, spec, "synthetic");
    }
  }
  return path;
}

// A target whose mean is the response at (mu_gg, mur_gb) = (0.78, 0.30), scatter about a tenth of
// the lab's so that the calibrated point is sharply defined.
inline ImpactSet target_set() {
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

}  // namespace ricochet::dem::test
