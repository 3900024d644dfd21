// The score test of a candidate effect and the effects' declared signatures (Effect::signature()),
// used by diagnose() to screen generated candidates and to cite evidence. Internal to the
// diagnosis module.
//
// Score test: the base model's directions X (d prediction / d parameter, scaled by the error
// denominators, stacked over releases and observables) and its scaled in-sample residuals z,
// both projected off the columns of X. A candidate's direction s (the change of the scaled
// predictions when one added parameter moves from neutral by `probe_fraction` of its range),
// projected the same way, correlates with z by r = z.s / (|z| |s|): how much of the residual the
// effect could explain that the base parameters cannot (Rao's score test in correlation form).
// Positive r: moving the parameter up from neutral moves the predictions towards the data.
#pragma once

#include <Eigen/Dense>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "diagnosis/diagnose.hpp"

namespace ricochet::diagnosis::detail {

struct Directions {
  Eigen::MatrixXd X;                              // base parameter directions
  Eigen::VectorXd z;                              // scaled in-sample residuals, projected
  Eigen::MatrixXd proj;                           // I - X (X^T X)^-1 X^T
  std::vector<std::pair<std::size_t, int>> rows;  // (release, observable)
};

Directions base_directions(const Model& warm, const Shape& shape, const ImpactSet& set,
                           const Assessment& base, const AssessOptions& o);

/// The score-test correlation of `cand` (the warm base model plus the effect at neutral): the
/// largest in magnitude over its calibrated parameters `added`.
double signature_r(const Directions& dirs, const Model& cand, const Shape& shape,
                   const ImpactSet& set, const std::vector<std::size_t>& added,
                   const AssessOptions& o, double probe_fraction);

/// The registry of the options (built-ins and plugins by default).
const EffectRegistry& registry_of(const DiagnoseOptions& o);

/// The named effects as laws with numbers (Effect::law), "; "-separated, at `values` (the full
/// parameter vector of `model`, which holds every effect named).
std::string law_of(const Model& model, std::span<const double> values,
                   const std::vector<std::string>& effects, const EffectRegistry& registry);

/// What the effect stands for: its declared meaning, else its summary.
std::string meaning_of(const Effect& effect);

/// The effect's declared signature trends that are significant in the base model's residual and
/// parameter trends, as sentences.
std::vector<std::string> signature_matches(const Effect& effect, const Baseline& b);

}  // namespace ricochet::diagnosis::detail
