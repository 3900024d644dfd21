// Monte Carlo propagation of parameter distributions through the collision model and comparison
// of reflected-velocity CDFs with measurements (Garcia et al. 2020, section 4.3, Figs. 15-16),
// and direct calibration of the input ranges against the measured CDFs.
//
// A run draws every varied parameter from its distribution (inverse-CDF of independent uniform
// numbers from OpenTURNS' generator, explicit seed), takes the incident state (fixed, e.g. the
// paper's (2.9, -2.3, -65), or one of a data set's measured incident states, resampled with
// replacement), and for non-disc blocks the orientation (the impact's alpha_in when resampled
// and present, else uniform over one symmetry period), then simulates the collision. Runs go
// to the engine in chunks (simulate_batch: parallel and vectorised); after each chunk the
// progress bar advances (terminal only) and an optional callback receives the chunk (HDF5
// append + flush, so a killed run can resume from the last chunk).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/option_problems.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"
#include "uq/distribution.hpp"

namespace ricochet::uq {

struct MonteCarloOptions {
  std::size_t runs = 50000;
  std::uint64_t seed = 1;
  /// bulk_engine_options (dt = 1e-5 s, max_time_s = 0.1 s): a rebound not over by then is a
  /// failed run (status no_rebound), excluded from the CDFs and counted; threads: 0 = all.
  EngineOptions engine = bulk_engine_options();
  /// Fixed incident state (m/s, m/s, rad/s), used unless `incident` is set.
  Vel3 vin = {kPaperVin[0], kPaperVin[1], kPaperVin[2]};
  /// Resample incident states (and alpha_in when present) from these releases.
  const ImpactSet* incident = nullptr;
  /// Orientation range of non-disc blocks without a measured alpha_in [rad] (one period).
  double alpha_min_rad = -M_PI / 3, alpha_max_rad = M_PI / 3;
  std::size_t chunk = 5000;  ///< runs per engine call / progress step / HDF5 append
  bool progress = true;      ///< progress bar on stderr (only when it is a terminal)

  /// The allowed ranges (problems(); the command line shows them in --help, kAlphaRad in
  /// degrees). runs: two at least, or the reflected velocities have no standard deviation; 1e9
  /// bounds the random numbers drawn before the first run. alpha_min_rad < alpha_max_rad, both
  /// within half a turn of 0.
  static constexpr OptionRange kRuns{2, 1e9};
  static constexpr OptionRange kAlphaRad{-M_PI, M_PI};
  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// run_monte_carlo calls it at its entry.
  OptionProblems problems() const;
};

/// All runs of a Monte Carlo, row per run.
struct MonteCarloResult {
  std::vector<std::string> varied;  ///< names of the varied parameters
  std::vector<double> inputs;       ///< runs x varied, row-major
  std::vector<Vel3> vin;            ///< incident state of each run
  std::vector<double> alpha_rad;    ///< orientation of each run
  std::vector<Vel3> vout;           ///< reflected velocity of each run
  std::vector<int> status;          ///< CollisionStatus of each run
  double seconds = 0;
  std::size_t size() const { return vout.size(); }
  /// One component of V_out over the runs that rebounded (status ok).
  std::vector<double> component(int k) const;
};

/// The random numbers of a Monte Carlo, fixed by the seed: uniforms for the parameters (runs x
/// varied), the index of the resampled incident state and the orientation uniform per run.
/// Reusing them across evaluations gives common random numbers (smooth objectives).
struct RandomDraws {
  std::vector<double> u_params;  ///< runs x varied in [0, 1)
  std::vector<std::size_t> incident;
  std::vector<double> u_alpha;
};
RandomDraws draw(std::size_t runs, std::size_t varied, std::size_t incident_pool,
                 std::uint64_t seed);

/// Runs the Monte Carlo. Parameters not listed in `inputs` keep their model values. Throws
/// InputError for options with problems (MonteCarloOptions::problems), std::invalid_argument for
/// an unknown parameter name (listing the model's) or a distribution outside the parameter's
/// declared bounds. `first_run` > 0 resumes: runs before it are not
/// simulated (their rows stay zero in the result) and `on_chunk(begin, end, result)` is called
/// for the new chunks only.
using ChunkCallback =
    std::function<void(std::size_t begin, std::size_t end, const MonteCarloResult& result)>;
MonteCarloResult run_monte_carlo(const Model& model, const Shape& shape,
                                 const std::vector<ParameterInput>& inputs,
                                 const MonteCarloOptions& options,
                                 const ChunkCallback& on_chunk = {}, std::size_t first_run = 0);

/// Same, with given random draws (common random numbers).
MonteCarloResult run_monte_carlo(const Model& model, const Shape& shape,
                                 const std::vector<ParameterInput>& inputs,
                                 const MonteCarloOptions& options, const RandomDraws& draws);

/// Two-sample Kolmogorov-Smirnov comparison of each reflected component (vx, vy, w) between the
/// Monte Carlo runs and the measured releases (statistic and p-value from OpenTURNS via
/// stats::ks_two_sample), plus the Cramer-von Mises distance of the measured points to the
/// simulated CDF, omega^2 = (1/n) sum_i (F_sim(x_(i)) - (i - 1/2)/n)^2 (Anderson 1962).
struct CdfComparison {
  Vel3 ks{}, p_value{}, cvm{};
  std::size_t n_simulated = 0, n_measured = 0;
};
CdfComparison compare_cdfs(const MonteCarloResult& mc, const ImpactSet& measured);

/// Calibration of uniform input ranges directly against measured CDFs (the paper chose its
/// ranges by eye, Fig. 15): minimises the summed distance over vx, vy, w between the simulated
/// and measured reflected-velocity CDFs, over each varied parameter's (centre, half-width)
/// within its calibration bounds, with NLopt (derivative-free Subplex, robust to the residual
/// noise) from the given ranges. The random numbers are fixed (common random numbers), so the
/// objective changes smoothly with the ranges except for the KS jumps.
struct RangeFitOptions {
  MonteCarloOptions mc = [] {
    MonteCarloOptions o;
    o.runs = 2000;
    o.progress = false;
    return o;
  }();
  enum class Distance { kCramerVonMises, kKolmogorovSmirnov } distance = Distance::kCramerVonMises;
  int max_evaluations = 300;
  double xtol = 1e-3;  ///< in units of each parameter's bound range

  /// The allowed ranges (problems(); the command line shows them in --help): mc's are the Monte
  /// Carlo's (MonteCarloOptions::problems); 1e7 evaluations bound the search's time.
  static constexpr OptionRange kMaxEvaluations{1, 1e7};
  static constexpr OptionRange kXtol{0, 1, true, true};
  /// The problems of these options, mc's prefixed "mc."; calibrate_ranges calls it at its entry.
  OptionProblems problems() const;
};
struct RangeFitResult {
  std::vector<ParameterInput> ranges;  ///< calibrated uniform ranges
  double distance = 0;                 ///< objective at the optimum
  double initial_distance = 0;         ///< objective at the given ranges
  CdfComparison comparison;            ///< at the optimum, with the same draws
  int evaluations = 0;
  double seconds = 0;
};
RangeFitResult calibrate_ranges(const Model& model, const Shape& shape, const ImpactSet& measured,
                                const std::vector<ParameterInput>& start,
                                const RangeFitOptions& options);

/// Checks each input against the model: known name, support within the declared bounds.
void check_inputs(const Model& model, const std::vector<ParameterInput>& inputs);

}  // namespace ricochet::uq
