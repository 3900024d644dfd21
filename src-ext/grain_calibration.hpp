// Calibration of the resolved bed's grain-scale parameters against measured rebounds (issue 11):
// a kriging surrogate of the resolved V_out over the grain parameters that a campaign sampled
// ([design.sample], campaign_design.hpp), validated by leave-one-out, its Sobol indices (the
// "abacus": which grain parameter moves which rebound component), and the grain parameters whose
// predicted V_out matches a target (the lab's mean rebound).
//
// Model (Santner, Williams and Notz 2003, ch. 3; OpenTURNS KrigingAlgorithm): for each V_out
// component c, y_c(x) = beta_c + Z_c(x) + eps, Z a Gaussian process with a Matern 5/2 covariance
// over the parameters scaled to [0, 1], eps the replicate noise of a design point's mean (pooled
// within-point variance / replicas). The calibrated point minimises the expected standardised
// misfit  J(x) = sum_c [(m_c(x) - t_c)^2 + s_c(x)^2] / sd_c^2,  m_c and s_c^2 the kriging mean and
// variance, t_c and sd_c the target's mean and standard deviation: the posterior expectation of
// the squared distance in target standard deviations, which favours regions the design supports.
// The search is confined to where the bed is sand-like (the solid fraction's kriging within a
// band, grain_packing.hpp) and where the design's blocks rebound (rebound_region.hpp).
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "impact/impact_set.hpp"
#include "params.hpp"

namespace ricochet::dem {

struct GrainCalibrationOptions {
  /// Parameters ("bed.NAME" / "block.NAME") of the surrogate. Empty: every bed.* and block.*
  /// parameter that takes more than one value in the campaign (bed.seed excluded).
  std::vector<std::string> parameters;
  std::string where;             ///< impact-set filter applied to the campaign's /impacts first
  std::uint64_t seed = 1;        ///< OpenTURNS seed of the Sobol and search samples
  std::size_t sobol_n = 20000;   ///< base sample size of the Saltelli estimator on the surrogate
  std::size_t search_n = 20000;  ///< candidate points of the misfit search before the local polish
  /// The campaign's bed cache folder (its `cache_dir`): when set, each design point's bed packing
  /// is measured on its restart file (bed.hpp, measure_packing; needs MPI initialised) and a
  /// kriging surrogate of the solid fraction is fitted beside V_out's.
  std::string bed_cache;
  /// Bulk constraint of a sand-like bed [lo, hi] (needs bed_cache): the calibrated point is
  /// searched only where the solid fraction's kriging mean is within it. Empty: no constraint.
  std::vector<double> solid_fraction;
  /// A bed that neither the campaign file records (/dem/beds) nor bed_cache holds gets its solid
  /// fraction from its grain count (bed.hpp, GrainCountPacking) and the recorded beds of the same
  /// geometry (every bed.* value that is not a surrogate input, bed.seed aside), instead of an
  /// error. Needs bed_cache.
  bool packing_from_grain_count = false;
  /// The rebound region (rebound_region.hpp): the calibrated point is searched only where the
  /// indicator kriging of the design's rebounds is at least this probability (the default: the
  /// lab's 28 rebounds in 28 releases, rebound_region.hpp). 0: no constraint. No constraint
  /// either when every counted impact of the design rebounded.
  double rebound_threshold = 0.9;
};

/// The grain-count estimate of one geometry's beds (GrainCalibrationOptions::
/// packing_from_grain_count): the beds estimated, how many recorded beds it rests on and its
/// leave-one-out error on them.
struct GrainCountEstimate {
  std::string geometry;           ///< "bed.NAME=VALUE ..." of the group
  std::vector<std::string> beds;  ///< bed keys estimated
  std::size_t references = 0;
  double loo_max_abs = NAN;  ///< [-], NaN with one reference
};

/// One design point: a set of grain parameters and its replicas' mean rebound.
struct GrainPoint {
  std::vector<double> x;  ///< parameter values (units of the decks)
  Vel3 mean{};            ///< mean V_out of the replicas (m/s, m/s, rad/s)
  Vel3 loo{};             ///< leave-one-out prediction of `mean`
  std::size_t replicas = 0;
  std::vector<std::string> ids;
  double solid_fraction = NAN;  ///< measured on the point's bed(s) (mean), NaN without bed_cache
  double solid_fraction_loo = NAN;  ///< leave-one-out prediction of `solid_fraction`
  /// Where `solid_fraction` comes from: "recorded" (the file's /dem/beds), "measured" (the cache),
  /// "grain count" (GrainCountEstimate), or several joined by '+' for a point on several beds.
  std::string solid_fraction_source;
};

/// One design point's outcomes, rebounds or not (rebound_region.hpp, tally_rebounds).
struct ReboundTally {
  std::vector<double> x;  ///< parameter values (units of the decks)
  std::size_t rebounds = 0, counted = 0;
  std::vector<std::string> missed;  ///< ids of its counted impacts that did not rebound
  double loo = NAN;                 ///< leave-one-out indicator prediction of rebounds / counted
};

struct GrainCalibrationResult {
  std::string source;                   ///< the campaign file
  std::vector<std::string> parameters;  ///< surrogate inputs
  std::vector<double> lower, upper;     ///< their sampled ranges
  std::vector<double> deck_default;     ///< their values in the decks (grain-defaults.in etc.)
  std::vector<GrainPoint> points;
  std::size_t failed = 0;            ///< impacts of the campaign that did not rebound
  Vel3 replicate_sd{};               ///< pooled within-point standard deviation of V_out
  std::array<double, 3> q2{};        ///< leave-one-out Q2 per component
  std::array<double, 3> rmse_loo{};  ///< leave-one-out root-mean-square error per component
  /// Sobol indices on the surrogate, [component][parameter], with 95 % bootstrap intervals.
  std::array<std::vector<double>, 3> first, total, first_lo, first_hi, total_lo, total_hi;
  /// The target (mean and standard deviation of V_out over its impacts) and its size.
  Vel3 target_mean{}, target_sd{};
  std::size_t target_n = 0;
  std::vector<double> best;     ///< the calibrated parameters
  Vel3 best_mean{}, best_sd{};  ///< surrogate mean and standard deviation at `best`
  double best_misfit = 0;       ///< J(best)
  /// With bed_cache: the solid fraction's surrogate at `best` (mean, sd), its leave-one-out Q2,
  /// and the band searched (empty without one).
  double best_solid_fraction = NAN, best_solid_fraction_sd = NAN, solid_fraction_q2 = NAN;
  std::vector<double> solid_fraction_band;
  std::vector<GrainCountEstimate> grain_count_estimates;  ///< empty unless some bed needed one
  /// The rebound region (GrainCalibrationOptions::rebound_threshold): every design point's
  /// outcomes, the threshold searched (0: none; also 0 when every counted impact rebounded), the
  /// indicator's leave-one-out agreement with the points' observed side of 0.5, the share of the
  /// sampled box inside the region, and the indicator at `best` (NaN without a region).
  std::vector<ReboundTally> rebound_points;
  double rebound_threshold = 0;
  double rebound_loo_agreement = NAN, rebound_box_fraction = NAN, best_rebound = NAN;
  /// Share of the sampled box where the search may place `best`: inside the solid-fraction band
  /// and the rebound region (1 without either).
  double admissible_fraction = 1;
  /// Fraction of the sampled box where every component's surrogate mean is within 0.5 target
  /// standard deviations of the target mean (the acceptable set: how unique `best` is).
  double acceptable_fraction = 0;
  /// The abacus: for each parameter k, the surrogate along a grid of that parameter with the
  /// others at `best`: grid[k], mean[k][c][i], sd[k][c][i].
  std::vector<std::vector<double>> grid;
  std::vector<std::array<std::vector<double>, 3>> curve_mean, curve_sd;
  /// With a rebound region: the indicator along the same grids, curve_rebound[k][i].
  std::vector<std::vector<double>> curve_rebound;
  double seconds = 0;
};

/// Reads the campaign's rebounds (its /impacts) and their grain parameters, groups replicas
/// (same parameters), fits the surrogate, validates it, computes Sobol indices and calibrates
/// to the V_out distribution of `target` (e.g. the lab cylinders). Throws InputError naming the
/// file when there are fewer design points than parameters + 2, a parameter is unknown or not
/// numeric, or the target is empty.
GrainCalibrationResult calibrate_grains(const std::string& campaign_h5, const Decks& decks,
                                        const ImpactSet& target,
                                        const GrainCalibrationOptions& options);

/// The smallest and largest measured solid fraction of the design's beds (NaN without
/// bed_cache).
std::array<double, 2> solid_fraction_range(const GrainCalibrationResult& r);

/// JSON document (nlohmann dump) of a result: keys documented in docs/commands/calibrate-grains.md.
std::string grain_calibration_json(const GrainCalibrationResult& r);

/// Figures (SVG) into `dir`: grains_sobol.svg (first and total indices per parameter, per V_out
/// component, with intervals), grains_loo.svg (leave-one-out prediction against the replicas'
/// mean), grains_abacus.svg (each component against each parameter through the calibrated
/// point, surrogate mean +- 2 sd, design points, target band), and with a rebound region
/// grains_rebound.svg (the indicator against each parameter through the calibrated point, the
/// threshold, each design point's rebound fraction). Returns the files written.
std::vector<std::string> write_grain_calibration_figures(const GrainCalibrationResult& r,
                                                         const std::string& dir);

}  // namespace ricochet::dem
