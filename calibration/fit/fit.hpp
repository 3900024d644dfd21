// Calibration of contact-model parameters against measured rebounds (Garcia et al. 2020,
// section 4.2, Eq. 7, Table 4), with identifiability, population fits and predictions.
//
// What is calibrated: the parameters of calibration_model(model, options.error): those of the
// Model flagged calibrated (Model::calibrated_indices(), the paper's law: en2, mu, muR), plus,
// when the error compares the maximum penetration or the contact duration (ErrorOptions), the
// parameters that effects declare identified by those features (ParameterSpec::identified_by
// = IdentifiedBy::kContactFeatures: the paper's kn), within the model's calibration bounds
// (Model::lower/ upper). Every other parameter stays at its model value (the paper's kt, kr; and kn
// on rebound velocities alone, which hardly depend on it). Which stiffnesses the features identify
// was measured on sets of an independent simulator (docs/diagnosis.md, "Which stiffnesses the
// contact features identify"): kn identified (population fits of 40 releases with lab-like
// noise: +4 % +- 9 % over 5 sets with one constant denominator per contact term, fit/error.hpp;
// +18 % with denominators that followed each release's reading); kt and kr not (their
// intervals reach a bound).
//
// Search variables: each calibrated parameter is mapped to [0, 1] linearly between its bounds,
// or logarithmically when its bounds are positive and span two decades or more (log_scaled():
// the stiffnesses, whose bounds span four), so that a step, a start design and the interval
// resolution are relative there (1 % of the log range of kn is 9.6 % of its value).
//
// Per-release fit (calibrate_release): minimise Eq. 7 (fit/error.hpp) for one release with
// NLopt BOBYQA (Powell's derivative-free trust-region method; the paper used Powell's conjugate
// directions), multi-start: a Latin hypercube design of the calibration box (OpenTURNS, explicit
// seed, plus the model's own values) is evaluated in one vectorised engine batch and BOBYQA
// starts from its best `starts` points. The best end point wins.
//
// Incidence angle of non-disc blocks (triangles): the lab data do not contain alpha_in. When an
// impact lacks it, alpha_in is a NUISANCE parameter, fitted per release together with the
// model parameters within [alpha_min, alpha_max] (default [-60, 60] degrees: the lab triangle has
// 120-degree symmetry, so this range holds every orientation once), and reported with its own
// interval. AlphaMode::kMarginal instead averages Eq. 7 over a rule of orientations (the
// expected error for an unknown orientation); population fits and predictions use that mode,
// since the reflected velocity of a held-out release cannot be used to choose its orientation.
// An impact with alpha_in uses it as measured. The rules (fit/orientation_rule.hpp, issue 35):
// a coarse search rule (AlphaOptions::marginal_points) for the multi-start, whose best ends are
// then polished by BOBYQA on the refined rule (polish_points), which also gives every prediction
// and its quadrature error; each release's rule is shifted by its own fraction of a cell. On the
// lab triangles the held-out error then moves by less than 1 % when either rule is refined
// (docs/diagnosis.md, "Orientation average").
//
// Identifiability (not in the paper): the near-optimal set of a release is every parameter
// vector whose Eq. 7 is within Delta of the optimum, Delta = sum_k (sigma_k / d_k)^2 the expected
// Eq. 7 of the true parameters under measurement noise (fit/error.hpp, noise_threshold()). sigma
// comes from the impact's sigma_vout, else from FitOptions::sigma; with contact terms, Delta
// also counts (sigma_h / d_h)^2 + (sigma_T / d_T)^2 (FitOptions::sigma_penetration_m,
// sigma_contact_duration_s; contact_noise_threshold()). For each parameter the
// interval [lo, hi] of its values over that set is found by a profile walk: step away from the
// optimum, re-optimise all other parameters (BOBYQA, warm start, stop as soon as the threshold is
// met), double the step while inside, then bisect to the resolution. Only verified near-optimal
// points enter the interval (an inner estimate at resolution `interval_resolution`). An end that
// reaches the calibration bound means that side is NOT identified:
//   identified          lo and hi inside the bounds        "en2 in [0.12, 0.18]"
//   lower_bound_only    hi reaches the upper bound          "mu >= 0.31, upper bound not
//   identified" upper_bound_only    lo reaches the lower bound          "muR <= 0.20, lower bound
//   not identified" not_identified      both reach the bounds
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/option_problems.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"
#include "fit/error.hpp"
#include "fit/lab_noise.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::fit {

class CollisionMemo;

/// Whether `error` has a contact term (ErrorOptions::penetration or contact_duration).
bool uses_contact_terms(const ErrorOptions& error);

/// `error` with each contact term switched on when every release of `set` carries its feature
/// (penetration, contact_duration), off otherwise (empty set: off), and each term switched on
/// given its one denominator for the set (fit/error.hpp, ErrorOptions::penetration_scale_m,
/// contact_duration_scale_s): the set's mean measured value, at least the term's floor. A
/// scale already set (> 0) is kept: it was decided on the set the caller chose (a per-release
/// fit of one release of a set keeps the set's scale; a fold's options are resolved on its
/// training releases before they get here). The rule by which the diagnosis and `ricochet
/// calibrate` decide that, and how, a set's features enter the error.
ErrorOptions with_contact_terms(const ErrorOptions& error, const ImpactSet& set);

/// The model a fit with `error` calibrates: THE decision of which parameters are fitted (file
/// comment). `model` itself when `error` compares rebound velocities only; otherwise `model`
/// with every parameter that its effect declares identified by the contact features
/// (IdentifiedBy::kContactFeatures: the normal stiffness kn) flagged calibrated too, unless the
/// model holds it (Model::held: a law given with its values, e.g. to predict durations). Idempotent.
/// Every fit function applies it; callers that enumerate the calibrated parameters themselves (the
/// diagnosis, the calibrate command's output) apply it to the model they hold, so that both see the
/// same parameters.
Model calibration_model(const Model& model, const ErrorOptions& error);

/// Whether a parameter with calibration bounds [lower, upper] is searched in log(value):
/// lower > 0 and upper >= 100 lower (file comment).
bool log_scaled(double lower, double upper);

/// Added to Eq. 7 when the engine reports no rebound (block still in contact at max_time_s or
/// never touching): such parameter values cannot explain a measured rebound.
inline constexpr double kFailedRebound = 10.0;

/// Treatment of an unknown incidence angle (non-disc shapes, impacts without alpha_in).
enum class AlphaMode {
  kFit,       ///< nuisance parameter fitted per release within [min_rad, max_rad]
  kMarginal,  ///< Eq. 7 averaged over `marginal_points` orientations evenly spread over the range
};
const char* alpha_mode_name(AlphaMode mode);

/// How a cold population fit with orientation-averaged releases searches (issue 35, item 3).
enum class OrientationSearch {
  /// BOBYQA from the `starts` best design points on the search rule, the best `polish_ends`
  /// ends polished on the refined rule.
  kMultiStart,
  /// Every collision on the refined rule: the design, then rounds of a response surface's
  /// minima (fit/surrogate_search.hpp), the best point polished by BOBYQA. A fit without a
  /// design (a local refinement) or without a refined rule searches by kMultiStart.
  kSurface,
};
/// "multistart", "surface" (the command line's values of --orientation-search).
const char* orientation_search_name(OrientationSearch search);
/// The search named `name`; throws std::invalid_argument ("'NAME': use multistart or surface").
OrientationSearch orientation_search_from(const std::string& name);

struct AlphaOptions {
  AlphaMode mode = AlphaMode::kFit;
  double min_rad = -M_PI / 3;  ///< -60 degrees
  double max_rad = M_PI / 3;  ///< +60 degrees: with min_rad, one period of a 3-fold symmetric block
  /// Orientations of the search rule (fit/orientation_rule.hpp): the start design and BOBYQA runs
  /// of a population fit.
  int marginal_points = 6;
  /// Orientations of the refined rule: the polish of a population fit's best ends, per-release
  /// marginal fits and every prediction; 0: the search rule throughout (no polish).
  int polish_points = 24;
  /// Ends of the search polished on the refined rule (the best by the search rule's error). One
  /// end polished gave the lab triangles a held-out error 2 % above three (0.900 against 0.884).
  int polish_ends = 3;
  /// BOBYQA step tolerance of the search's runs when they are polished, in units of the bound
  /// range (FitOptions::xtol for the polish): the search only has to find the basin.
  double search_xtol = 1e-3;
  /// The global search of cold population fits (OrientationSearch).
  OrientationSearch search = OrientationSearch::kMultiStart;
  /// Rounds of the response surface at most (kSurface; SurrogateSearchOptions::rounds).
  int surface_rounds = 24;
  /// Shift each release's rules by a fraction of a cell drawn from its id (orientation_rule.hpp);
  /// off: the midpoints of equal cells for every release.
  bool rotate = true;
  /// The rule of predictions and per-release marginal fits.
  int prediction_points() const { return polish_points > 0 ? polish_points : marginal_points; }
};

enum class Identifiability { kIdentified, kLowerBoundOnly, kUpperBoundOnly, kNotIdentified };
/// "identified", "lower_bound_only", "upper_bound_only", "not_identified" (JSON and HDF5 values).
const char* identifiability_name(Identifiability status);

/// The near-optimal interval of one parameter (see the file comment).
struct ParameterInterval {
  std::string name;
  std::string unit;
  double value = NAN;                     ///< value at the optimum
  double lo = NAN, hi = NAN;              ///< near-optimal interval (verified points)
  double bound_lo = NAN, bound_hi = NAN;  ///< calibration bounds
  bool lo_at_bound = false, hi_at_bound = false;
  Identifiability status = Identifiability::kNotIdentified;
  /// Human-readable verdict, e.g. "mu >= 0.31, upper bound not identified: the rebound does not
  /// depend on mu above it (the contact sticks)".
  std::string statement;
  /// Profile points visited by the walk: (value, smallest Eq. 7 found with the others free).
  std::vector<std::array<double, 2>> profile;
};

struct FitOptions {
  /// Engine settings (bulk_engine_options: dt = 1e-5 s as the paper, max_time_s = 0.1 s); a
  /// rebound not over by then is a failed rebound, scored Eq. 7 + kFailedRebound.
  /// `engine.threads` is ignored inside a release fit.
  EngineOptions engine = bulk_engine_options();
  ErrorOptions error;      ///< Eq. 7 denominators
  std::uint64_t seed = 1;  ///< seed of the Latin hypercube start design
  int starts = 4;          ///< BOBYQA runs per fit, from the best design points
  /// Size of the start design besides the model's own values; 0 = 16 per fitted variable;
  /// -1 = none (a local refinement from the model's values).
  int design_points = 0;
  int max_evaluations = 300;  ///< per BOBYQA run
  double xtol = 1e-3;         ///< BOBYQA step tolerance, in units of the bound range
  AlphaOptions alpha;         ///< unknown incidence angle of non-disc blocks
  bool intervals = true;      ///< compute near-optimal intervals (identifiability)
  /// Measurement standard uncertainty of V_out {m/s, m/s, rad/s} when an impact has no
  /// sigma_vout: the lab's (LabNoise, paper Table 1). Each in [1e-12, 1e6].
  Vel3 sigma = LabNoise::vout;
  /// Standard uncertainty of the maximum penetration [m] and of the contact duration [s] in
  /// the near-optimal threshold when the error has those terms (noise_threshold): the lab's
  /// (LabNoise).
  double sigma_penetration_m = LabNoise::penetration_m;
  double sigma_contact_duration_s = LabNoise::contact_duration_s;
  double threshold_scale = 1.0;  ///< multiplies Delta (e.g. 4 for "two sigma"); [1e-6, 1e6]
  /// Interval resolution, as a fraction of each parameter's bound range.
  double interval_resolution = 0.01;
  int threads = 0;  ///< OpenMP threads over releases (calibrate_releases) or batches; 0 = default
  /// Collisions shared with other fits of the same model, shape and engine settings
  /// (fit/collision_memo.hpp): the fold fits of one assessment. Null: none kept.
  std::shared_ptr<CollisionMemo> memo;
  /// A term added to the population fits' objective (calibrate_population, and so every fold
  /// fit of an assessment), evaluated at every point the search visits with the model being
  /// fitted, the full parameter vector (model order) and the releases being fitted (a fold fit's
  /// training releases only); empty: Eq. 7 alone. Issue 33's force histories
  /// (diagnosis/history_objective.hpp) are one. Release fits (calibrate_release) ignore it; a
  /// population fit's `error` includes it. Must be thread-safe and deterministic.
  std::function<double(const Model& model, std::span<const double> params, const ImpactSet& set)>
      extra_objective;

  /// The allowed ranges (problems(); the command line shows them in --help). design_points: -1
  /// is no design (see above), 1e6 bounds one engine batch; marginal points: one orientation is
  /// no average; alpha.min_rad < alpha.max_rad, both within one turn.
  static constexpr OptionRange kStarts{1, 1000};
  static constexpr OptionRange kDesignPoints{-1, 1e6};
  static constexpr OptionRange kMaxEvaluations{1, 1e9};
  static constexpr OptionRange kUnitFraction{0, 1, true, true};  ///< xtol, interval_resolution
  static constexpr OptionRange kMarginalPoints{2, 3600};
  static constexpr OptionRange kPolishPoints{0, 3600};  ///< 0 = none; 1 is refused (no average)
  static constexpr OptionRange kPolishEnds{1, 1000};
  static constexpr OptionRange kSurfaceRounds{1, 1000};
  static constexpr OptionRange kAlphaRad{-M_PI, M_PI};
  static constexpr OptionRange kSigma{1e-12, 1e6};  ///< every standard uncertainty
  static constexpr OptionRange kThresholdScale{1e-6, 1e6};

  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// calibrate_release, calibrate_releases, calibrate_population and heldout_predictions call it
  /// at their entry.
  OptionProblems problems() const;
};

/// Result of one release's calibration.
struct ReleaseFit {
  std::string id;
  std::vector<std::string> names;       ///< all model parameter names (model order)
  std::vector<double> params;           ///< all model parameter values at the optimum
  std::vector<std::size_t> calibrated;  ///< indices of the fitted parameters in `params`
  double error = NAN;                   ///< Eq. 7 at the optimum
  Vel3 measured{}, simulated{};         ///< V_out measured and simulated at the optimum
  Vel3 terms{};                         ///< the three terms of Eq. 7 at the optimum
  double threshold = NAN;               ///< Delta of the near-optimal set
  /// Incidence angle [rad] used at the optimum; NaN for discs or in marginal mode.
  double alpha_rad = NAN;
  std::string alpha_source;                         ///< "none" (disc), "data", "fitted", "marginal"
  std::optional<ParameterInterval> alpha_interval;  ///< when fitted and intervals requested
  std::vector<ParameterInterval> intervals;         ///< per calibrated parameter, same order
  std::vector<double> start_errors;                 ///< Eq. 7 at the end of each BOBYQA run
  int evaluations = 0;                              ///< collisions simulated (fit + intervals)
  double seconds = 0;                               ///< wall time of this release
  CollisionStatus status = CollisionStatus::kOk;    ///< engine status at the optimum

  double value(const std::string& name) const;  ///< throws std::invalid_argument if unknown
  const ParameterInterval* interval(const std::string& name) const;  ///< nullptr if absent
};

/// Calibrates one release (see the file comment). Throws std::invalid_argument if the model
/// has no calibrated parameter.
ReleaseFit calibrate_release(const Model& model, const Shape& shape, const Impact& impact,
                             const FitOptions& options = {});

/// Hooks for long runs: skip releases already done (resume) and receive each result as soon as
/// it is ready (called in a critical section, in completion order) to write it incrementally.
struct ReleaseHooks {
  std::function<bool(std::size_t index)> already_done;
  std::function<void(std::size_t index, const ReleaseFit& fit)> on_done;
};

/// Calibrates every release of `set`, in parallel over releases (OpenMP, options.threads).
/// Deterministic: each release's result depends only on the model, the shape, the release and
/// the options, not on the thread count or the order. Skipped releases are left default
/// (empty id) in the returned vector.
std::vector<ReleaseFit> calibrate_releases(const Model& model, const Shape& shape,
                                           const ImpactSet& set, const FitOptions& options = {},
                                           const ReleaseHooks& hooks = {});

/// Predicted reflected velocity of one release.
struct Prediction {
  Vel3 vout{};      ///< (m/s, m/s, rad/s); the mean over orientations in marginal mode
  Vel3 vout_std{};  ///< spread over orientations (marginal mode), else 0
  /// Marginal mode: the mean and spread over the even- and the odd-numbered orientations of the
  /// rule, two interleaved rules of half the points (fit/orientation_rule.hpp); else vout and
  /// vout_std. The error of a half rule minus the full rule's estimates the quadrature error.
  std::array<Vel3, 2> vout_half{}, vout_std_half{};
  /// max over the halves of |half - full|, per component (m/s, m/s, rad/s); 0 unless marginal.
  Vel3 vout_quadrature_error{};
  int orientations = 1;             ///< points averaged over (the rule's size in marginal mode)
  double penetration_m = NAN;       ///< maximum penetration [m] (mean over orientations)
  double contact_duration_s = NAN;  ///< contact duration [s] (mean over orientations)
  /// The same two means over the half rules (see vout_half) [m], [s].
  std::array<double, 2> penetration_half_m{NAN, NAN}, contact_duration_half_s{NAN, NAN};
  double alpha_rad = NAN;    ///< orientation used; NaN for discs and marginal mode
  std::string alpha_source;  ///< "none", "data", "given", "marginal"
  CollisionStatus status = CollisionStatus::kOk;  ///< worst engine status over orientations
};

/// Predicts V_out for every release of `set` with the full parameter vector `params` (model
/// order). Orientation of non-disc blocks: the impact's alpha_in if present, else
/// `alpha_rad[i]` if given (e.g. per-release fitted values), else the orientation rule
/// (options.alpha.prediction_points(), shifted per release). Runs one engine batch (parallel,
/// vectorised).
std::vector<Prediction> predict(const Model& model, const Shape& shape,
                                std::span<const double> params, const ImpactSet& set,
                                const FitOptions& options = {},
                                std::span<const double> alpha_rad = {});

/// Eq. 7 of each prediction against the set's measured V_out (plus the contact terms that
/// `options` turns on).
std::vector<double> prediction_errors(const ImpactSet& set,
                                      const std::vector<Prediction>& predictions,
                                      const ErrorOptions& options = {});

/// One parameter set for many releases: minimises the sum over releases of Eq. 7 (non-disc
/// blocks without alpha_in: the marginal, orientation-averaged Eq. 7).
struct PopulationFit {
  std::vector<std::string> names;
  std::vector<double> params;  ///< all model parameters at the optimum
  std::vector<std::size_t> calibrated;
  double error = NAN;                   ///< summed Eq. 7 at the optimum
  std::vector<double> release_errors;   ///< per release, same order as the set
  std::vector<Prediction> predictions;  ///< per release at the optimum
  /// Threshold of the population near-optimal set: mean per-release Delta (3 degrees of
  /// freedom, as per release), inflated by max(1, error / sum Delta) when the releases scatter
  /// more than the measurement noise (reduced chi-square).
  double threshold = NAN;
  std::vector<ParameterInterval> intervals;
  std::vector<double> start_errors;
  int evaluations = 0;  ///< objective evaluations (each one engine batch)
  double seconds = 0;
};
PopulationFit calibrate_population(const Model& model, const Shape& shape, const ImpactSet& set,
                                   const FitOptions& options = {});

/// Held-out predictions: the set is split into `folds` folds (release i in fold i % folds;
/// folds = set.size() is leave-one-out); each fold is predicted by a population fit on the
/// others. Returns per release the prediction and Eq. 7, plus the fold fits' parameters.
struct HeldOut {
  std::vector<Prediction> predictions;
  std::vector<double> errors;
  std::vector<std::vector<double>> fold_params;  ///< params of each fold's population fit
};
HeldOut heldout_predictions(const Model& model, const Shape& shape, const ImpactSet& set,
                            std::size_t folds, const FitOptions& options = {});

/// Releases of `set` whose shape matches `shape` (by name); throws InputError naming the data
/// file and the `shape` column when none does, listing the shapes present.
ImpactSet select_shape(const ImpactSet& set, const Shape& shape);

}  // namespace ricochet::fit
