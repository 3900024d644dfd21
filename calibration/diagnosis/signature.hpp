// The score test of a candidate effect and the effects' declared signatures (Effect::signature()),
// used by diagnose() to screen generated candidates and to cite evidence. Internal to the
// diagnosis module.
//
// Score test: the base model's directions X (d prediction / d parameter, scaled by the error
// denominators, stacked over releases and observables) and its scaled in-sample residuals z,
// both whitened release by release with the pooled covariance of the scaled in-sample residual
// vectors (S = L L^T over the observables, each release's block multiplied by L^-1: a GLS
// score, where each observable counts by its signal-to-noise ratio, not by its error
// denominator, and the correlation of V_out^x and omega_out residuals that the ground's
// friction scatter makes is not counted twice) and projected off the columns of X (and off the
// nuisance parameters' directions, IdentifiedBy::kContactFeatures: fixed parameters such as kn
// that rebound velocities do not identify, moved by half their value). A candidate's
// direction s (the change of the whitened predictions when one added parameter moves from neutral
// by `probe_fraction` of its range), projected the same way, gives
//   - the correlation r = z.s / (|z| |s|): how much of the residual the effect could explain
//     that the base parameters cannot (Rao's score test in correlation form; the screen);
//   - per release i, the score contribution u_i = sum over its observables of s z: the columns
//     of the robust score test (stats/score_tests.hpp), whose statistic is the test of the
//     candidate. The projection makes the score insensitive, to first order, to the error of
//     the base parameters' estimate, so the test holds whichever fit estimated them.
// Positive r or T: moving the parameter from neutral into its bounds moves the predictions
// towards the data. A parameter whose neutral value is a bound is tested one-sided.
#pragma once

#include <Eigen/Dense>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "diagnosis/diagnose.hpp"
#include "stats/score_tests.hpp"

namespace ricochet::diagnosis::detail {

struct Directions {
  Eigen::MatrixXd X;                              // base parameter directions (whitened)
  Eigen::VectorXd z;                              // whitened in-sample residuals, projected
  Eigen::MatrixXd proj;                           // I - X (X^T X)^-1 X^T
  std::vector<std::pair<std::size_t, int>> rows;  // (release, observable)
  Eigen::MatrixXd whiten;  // L^-1 over the used observables (block of one release)
};

Directions base_directions(const Model& warm, const Shape& shape, const ImpactSet& set,
                           const Assessment& base, const AssessOptions& o);

/// The score test of `cand` (the warm base model plus the effect at neutral): `r`, the
/// correlation of largest magnitude over its calibrated parameters `added`, and one column of
/// per-release score contributions per parameter, labelled `hypothesis`.
/// One added parameter's direction, kept for the confidence set of laws (confidence.cpp).
struct ScoreDirection {
  std::size_t parameter = 0;  ///< index in the candidate model
  Eigen::VectorXd s;          ///< whitened, projected change per unit of the parameter
  Eigen::VectorXd raw;        ///< change of the predictions per unit (SI, rows of Directions)
  /// Which way the parameter may move from neutral: +1 up, -1 down (neutral at a bound), 0 both.
  int allowed = 0;
};
struct Score {
  double r = NAN;
  std::vector<stats::ScoreColumn> columns;
  std::vector<ScoreDirection> directions;
};
Score score_of(const Directions& dirs, const Model& cand, const Shape& shape, const ImpactSet& set,
               const std::vector<std::size_t>& added, const AssessOptions& o, double probe_fraction,
               std::size_t hypothesis);

/// The change of `cand`'s predictions from `p0` (its predictions at its own values, the
/// candidate at neutral) to its predictions at `params`, divided by `step`, laid out like
/// `dirs.rows`: `raw` in SI units, `s` scaled, whitened and projected. With `step` the probe's
/// parameter step it is ScoreDirection's change per unit (score_of); with step 1, what a law at
/// a finite strength adds to the residual, without that linearisation (power.hpp).
struct FiniteChange {
  Eigen::VectorXd raw, s;
};
FiniteChange finite_change(const Directions& dirs, const Model& cand, const Shape& shape,
                           const ImpactSet& set, const std::vector<double>& params,
                           const std::vector<ObsPrediction>& p0, const AssessOptions& o,
                           double step = 1.0);

/// Per release, the sum over its rows (`dirs.rows`) of x_r y_r: a score's contributions u_i with
/// (x, y) = (direction, residual), or a direction's own gain per unit change a_i = |s_i|^2 with
/// x = y = s (power.hpp). `releases` entries.
std::vector<double> per_release_products(const Directions& dirs, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd& y, std::size_t releases);

/// Root mean square over releases, per observable, of a change of the predictions laid out like
/// `dirs.rows` (SI units, e.g. ScoreDirection::raw times a parameter change); NaN for an
/// observable that `use` leaves out.
Obs rms_per_observable(const Directions& dirs, const Eigen::VectorXd& change,
                       const std::array<bool, kObservables>& use);

/// The registry of the options (built-ins and plugins by default).
const EffectRegistry& registry_of(const DiagnoseOptions& o);

/// The named effects as laws with numbers (Effect::law), "; "-separated, at `values` (the full
/// parameter vector of `model`, which holds every effect named).
std::string law_of(const Model& model, std::span<const double> values,
                   const std::vector<std::string>& effects, const EffectRegistry& registry);

/// True when every parameter of the named effects that has a neutral value sits exactly at it in
/// `values` (the full parameter vector of `model`): the fit did not use the effects, whatever the
/// error did. False when any parameter moved, or when none of them declares a neutral value.
bool left_neutral(const Model& model, std::span<const double> values,
                  const std::vector<std::string>& effects, const EffectRegistry& registry);

/// What the effect stands for: its declared meaning, else its summary.
std::string meaning_of(const Effect& effect);

/// The effect's declared signature trends that are significant in the base model's residual and
/// parameter trends, as sentences. `base`: the model the trends were computed on, whose
/// parameters of the role a trend names ("param restitution") are its calibrated quantities.
std::vector<std::string> signature_matches(const Effect& effect, const Model& base,
                                           const Baseline& b);

}  // namespace ricochet::diagnosis::detail
