// The gap between a model's impacts (a resolved campaign, a synthetic set) and a measured set
// (the lab), component by component: means and standard deviations, the two-sample KS test, the
// same with the measurement's noise added to the model values, robust centres and scales, and
// the KS test against the measured set without its gross errors. Plus three set-level checks that
// say what the measured scatter is: the gross-error rule on the measurements alone, whether the
// measurements respond to their own measured inputs as the model does, and how the
// measured-minus-model residuals at the same releases co-vary.
//
// docs/resolved-calibration.md ("The lab's gross errors and the exit slip", "Packing from release
// to release") explains why each part is there; docs/commands/upscale.md lists the JSON keys.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "impact/impact_set.hpp"
#include "stats/robust.hpp"
#include "stats/stats.hpp"

namespace ricochet::stats {

/// One compared quantity (a V_out component, the exit slip, a calibrated parameter).
struct ComponentGap {
  std::string name;
  Summary model, measured;             ///< mean and sample sd of each side
  KsResult ks;                         ///< two-sample KS, model against all measurements
  std::optional<NoisyKsResult> noisy;  ///< the KS with the measurement noise (LabGapOptions)
  std::uint64_t noise_seed = 0;
  RobustSummary model_robust, measured_robust;  ///< median and MAD scale
  /// The measurements without the rows flagged as gross errors (absent when no row is kept out).
  std::optional<Summary> measured_core;
  std::optional<KsResult> ks_core;
};

/// `model` and `measured` values of one quantity (NaN skipped). `core` (same length as
/// `measured`, or empty) marks the measurements kept in the core comparison; `noise` adds the
/// measurement-noise KS test (sigma in the quantity's unit, draws, seed).
struct NoiseModel {
  double sigma = 0;
  std::size_t draws = 400;
  std::uint64_t seed = 1;
};
ComponentGap component_gap(const std::string& name, std::span<const double> model,
                           std::span<const double> measured, const std::vector<bool>& core = {},
                           const std::optional<NoiseModel>& noise = std::nullopt);

/// The gross-error rule (robust.hpp) on an impact set's six velocities: vin_x, vin_y, win,
/// vout_x, vout_y, wout. Reads the set alone.
GrossErrors gross_errors_of(const ImpactSet& set);
/// `set` without the releases gross_errors_of() flags; their ids go to `dropped` if given. The
/// comments gain a line naming them.
ImpactSet without_gross_errors(const ImpactSet& set, std::vector<std::string>* dropped = nullptr);

struct LabGapOptions {
  /// Measurement noise of (V_out^x [m/s], V_out^y [m/s], omega_out [rad/s]); absent = no
  /// noise test.
  std::optional<Vel3> noise_sigma;
  std::size_t noise_draws = 400;
  std::uint64_t seed = 1;
  /// Radius of a disc-shaped block [m]: adds the exit slip V_out^x + omega_out R (the bottom
  /// point's velocity at separation; 0 = the block leaves rolling). NaN = not a disc.
  double disc_radius_m = std::numeric_limits<double>::quiet_NaN();
};

/// Measured-minus-model residuals of V_out at the same releases. A model impact belongs to a
/// measured release when its id is the release's id, or the release's id followed by '-' (as
/// campaigns name their impacts, "C01-x_impact_frac0.26"); the model impacts of one release are
/// averaged. Whatever moves the measurements away from the model from release to release leaves
/// its mark in how the three residuals co-vary: a source that moves V_out^x and V_out^y together
/// (a denser or looser bed) correlates them positively, a local tilt of the surface (which
/// rotates V_out) negatively, independent reading noise not at all
/// (docs/resolved-calibration.md, "What the lab's residuals say").
struct PairedResiduals {
  std::size_t n = 0;           ///< releases matched
  std::array<double, 3> sd{};  ///< sample sd of each residual [m/s, m/s, rad/s]
  /// Pairs (vout_x, vout_y), (vout_x, wout), (vout_y, wout): Pearson r and its two-sided p.
  std::array<Correlation, 3> r{};
  /// Fisher-z 95 % interval of each r (Fisher 1915: atanh r is normal with sd 1/sqrt(n - 3)).
  std::array<std::array<double, 2>, 3> r_ci95{};
  std::array<double, 3> p_holm{};  ///< Holm over the three pairs
  /// The same pairs' r over the matched releases, of the measured values alone and of the
  /// model's alone: the residuals' correlation mixes both (the model's includes its response to
  /// the reading noise of the measured V_in it was run at).
  std::array<double, 3> r_measured{}, r_model{};
};
/// Absent when fewer than 5 releases are matched.
std::optional<PairedResiduals> paired_residuals(const ImpactSet& model, const ImpactSet& measured);

struct LabGap {
  /// vout_x, vout_y, wout, then slip_out [m/s] for a disc.
  std::vector<ComponentGap> components;
  /// The gross-error rule (robust.hpp) on the measured set's six velocities, measurements only.
  GrossErrors measured_gross_errors;
  std::vector<std::string> flagged_ids;
  /// Response of V_out component k to V_in component k, model against the measurements that
  /// the gross-error rule keeps, with Holm-adjusted p-values over the three components.
  std::array<ResponseCheck, 3> response{};
  std::array<double, 3> response_p_holm{};
  std::optional<PairedResiduals> residuals;  ///< absent when the sets share too few releases
};

/// Compares `model` with `measured` (both impact sets of one shape). Throws std::invalid_argument
/// if either set is empty.
LabGap lab_gap(const ImpactSet& model, const ImpactSet& measured, const LabGapOptions& options);

/// JSON of one quantity: dem_mean, dem_std, lab_mean, lab_std, difference, difference_in_lab_std,
/// ks_statistic, ks_p_value; robust {dem_median, dem_mad_sd, lab_median, lab_mad_sd,
/// difference_in_lab_mad_sd}; lab_core {n, mean, std, difference_in_core_std, ks_statistic,
/// ks_p_value} when a core was given; ks_with_lab_noise {sigma, draws, seed, median_p, p10,
/// share_p_above_0.05} with a noise model. ("dem" is the model side: the keys predate this file.)
nlohmann::json to_json(const ComponentGap& gap);
/// JSON of the set-level checks: lab_gross_errors [{id, why}], lab_response {vx, vy, w: {r_model,
/// r_lab, n_model, n_lab, z, p_value, p_holm}}, lab_residuals {n, sd {vout_x, vout_y, wout},
/// correlations {vout_x:vout_y, vout_x:wout, vout_y:wout: {r, ci95, p_value, p_holm, r_lab,
/// r_model}}} when the sets share releases.
nlohmann::json checks_json(const LabGap& gap);
/// Readable lines: one per quantity, then the checks.
std::string to_text(const LabGap& gap);
std::string to_text(const ComponentGap& gap);

}  // namespace ricochet::stats
