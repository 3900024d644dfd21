// Release-to-release scatter of the ground: the population distribution of a model's calibrated
// parameters, and the noise floor that includes it (issue 10, item 2).
//
// Rebound on sand is stochastic (Garcia et al. 2020, section 3: the transfer matrix is a random
// matrix; Table 4 gives each parameter a spread over releases). Without replicates, a model
// whose held-out error exceeds the measurement floor may be missing physics, or the ground may
// simply differ from release to release. The scatter is estimated by a linearised hierarchical
// (random-effects) fit of the base model's held-out residuals:
//   theta_i ~ N(theta_pop, diag(tau^2)),   r_i ~ N(0, S_i + J_i diag(tau^2) J_i^T),
// with r_i the release's held-out residuals (physical units), S_i the measurement variances of
// the noise floor (inflated by 1 + p / n_train, the held-out cost of estimating theta_pop), and
// J_i the derivatives of the predicted observables with respect to the calibrated parameters at
// the population optimum (finite differences). tau maximises the Gaussian likelihood over
// tau_j in [0, range_j] (cyclic golden-section search). The likelihood-ratio test of tau = 0
// (conservatively chi^2 with p degrees of freedom) says whether there is scatter beyond the
// measurement noise. The floor with scatter adds diag(J_i diag(tau^2) J_i^T) to S_i.
//
// Where the set has neither replicates nor declared uncertainty columns, the measurement
// variances themselves are fitted: S_i = diag(g^2) S_i^Table1, one scale g_k per observable,
// estimated jointly with tau (issue 31, 5b), g_k <= 1. The Table 1 constants (the paper's
// operator scale) then give the shape of S_i over releases and a ceiling; the floor's source
// reads "fitted". What
// separates noise from scatter is structure, not magnitude: the noise is independent between
// observables and has the same scale for every release, while the scatter correlates the
// observables through J_i and changes with the incident state. Where J_i is nearly the same for
// every release and diagonal, the split is weakly identified, and a deterministic effect whose
// residuals look like independent noise can still be absorbed by g (the detection benchmark's
// "The noise floor" table measures how often).
//
// What it means: tau describes ANY excess that a random spread of the parameters can absorb,
// deterministic missing physics included. The diagnosis therefore calls the excess "scatter"
// only when no candidate effect is supported and no residual or parameter trend survives the
// multiplicity control (diagnose.hpp); tau is then the population spread the data support.
#pragma once

#include <string>
#include <vector>

#include "diagnosis/assess.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::diagnosis {

struct PopulationScatter {
  std::vector<std::string> names;  ///< calibrated parameters
  std::vector<std::string> units;
  std::vector<double> value;  ///< population (full-set) values
  std::vector<double> sd;     ///< tau: between-release standard deviation, same units
  /// Whether the data constrain tau_j: setting it to 0 (the others at their optimum) costs at
  /// least 0.5 in log-likelihood. A parameter the rebound does not depend on (mu when the
  /// contact sticks) has a flat likelihood in tau_j: its spread is reported as not identified.
  std::vector<bool> identified;
  /// Whether the measurement noise was fitted with tau (the set has neither replicates nor
  /// declared uncertainties, and n >= 2 (observables + parameters)): then the variances are
  /// g_k^2 times the Table 1 fallback's, g_k = noise_scale[k] in [0.05, 1] (issue 31, 5b).
  bool noise_fitted = false;
  Obs noise_scale{1, 1, 1, 1, 1};
  /// The measurement floor: the fitted one when noise_fitted, else the floor given.
  NoiseFloor measurement;
  double lr = 0;            ///< likelihood-ratio statistic of tau = 0 (noise scale profiled)
  double p_value = 1;       ///< chi^2 (p dof) upper tail of lr: conservative
  NoiseFloor floor;         ///< the measurement floor plus the scatter
  Adequacy adequacy;        ///< of the base model against the floor with scatter
  std::string description;  ///< one sentence with the numbers
  bool computed = false;
};

/// Estimates the scatter (file comment). `warm`: the base model at its population optimum;
/// `base`: its assessment; `floor`: its measurement floor.
PopulationScatter population_scatter(const Model& warm, const Shape& shape, const ImpactSet& set,
                                     const Assessment& base, const NoiseFloor& floor,
                                     const AssessOptions& options);

nlohmann::json to_json(const PopulationScatter& s);

}  // namespace ricochet::diagnosis
