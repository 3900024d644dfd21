// The stochastic transfer-matrix rebound model (paper section 3, Eq. 2, Table 3, Figs. 11-12),
// the full 3x3 matrix beyond the paper, their leave-one-out comparison and the comparison of
// measured and predicted reflected velocities as distributions.
//
// Velocities are V = (vx [m/s], vy [m/s], omega [rad/s]) in the impact-set frame
// (impact/impact_set.hpp). Releases are unweighted, as in the paper.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "impact/impact_set.hpp"
#include "stats/stats.hpp"

namespace ricochet::transfer {

/// 3x3 matrix, row-major: m[i][j] multiplies component j of V_in in component i of V_out.
using Mat3 = std::array<std::array<double, 3>, 3>;

/// Paper Eq. 2: V_out_i = A_ii V_in_i, with A_ii drawn for each rebound from the uniform
/// distribution on [A_ii - dA_ii, A_ii + dA_ii] (Table 3 note). Dimensionless.
struct DiagonalModel {
  Vel3 a{};        ///< A_xx, A_yy, A_thetatheta
  Vel3 delta_a{};  ///< dA_xx, dA_yy, dA_thetatheta (half-widths, >= 0)
};

/// Eq. 2 identified on a set, with the sample moments it is built from.
struct DiagonalFit {
  DiagonalModel model;
  std::size_t n = 0;
  Vel3 mean_in{}, mean_out{};                     ///< <V_in_i>, <V_out_i>
  Vel3 min_in{}, max_in{}, min_out{}, max_out{};  ///< signed extrema per component
};

/// Eq. 2 exactly: A_ii = <V_out_i> / <V_in_i> and
/// dA_ii = 1/4 |max(V_out_i) / max(V_in_i) - min(V_out_i) / min(V_in_i)| (signed min and max, as
/// printed; this reproduces Table 3). Throws std::invalid_argument for an empty set or a zero
/// mean, minimum or maximum of an incident component.
DiagonalFit fit_diagonal(const ImpactSet& set);

/// V_out = M V_in fitted by ordinary least squares, one row of M per output component
/// (no intercept, like Eq. 2). Standard errors from the residual variance with n - 3 degrees of
/// freedom: se_ij = s_i sqrt([(X^T X)^-1]_jj).
struct FullFit {
  Mat3 m{};
  Mat3 se{};
  Vel3 residual_std{};          ///< s_i = sqrt(RSS_i / (n - 3)), units of V_out_i
  double condition_number = 0;  ///< of the n x 3 matrix of incident velocities (columns scaled
                                ///< to unit norm): large = off-diagonal terms poorly identified
  std::size_t n = 0;
};
/// Throws std::invalid_argument with fewer than 4 releases or rank-deficient incident velocities.
FullFit fit_full(const ImpactSet& set);

/// Least-squares diagonal model V_out_i = a_i V_in_i (the best diagonal in the same sense as the
/// full matrix, to separate "off-diagonal terms" from "estimator" in the comparison).
Vel3 fit_diagonal_lsq(const ImpactSet& set);

/// Leave-one-out predictive comparison: each release is predicted by models fitted on the
/// others. Errors are on the mean prediction (the expectation of Eq. 2 is A_ii V_in_i).
struct LooComparison {
  std::size_t n = 0;
  Vel3 rmse_constant{};      ///< predictor: mean V_out of the other releases (no model)
  Vel3 rmse_diagonal{};      ///< Eq. 2 (ratio of means), the paper's model
  Vel3 rmse_diagonal_lsq{};  ///< diagonal by least squares
  Vel3 rmse_full{};          ///< full 3x3 matrix by least squares
  /// Per component: the full matrix predicts held-out releases better than Eq. 2.
  std::array<bool, 3> full_improves{};
  std::vector<Vel3> predicted_diagonal, predicted_full;  ///< per release, in set order
};
/// Needs at least 5 releases (the full fit on n - 1 needs 4).
LooComparison leave_one_out(const ImpactSet& set);

/// Draws reflected velocities by Eq. 2: for each incident velocity, `replicates` rebounds, each
/// with its own A_ii ~ U[A_ii - dA_ii, A_ii + dA_ii] per component. Random stream: std::mt19937_64
/// seeded with `seed`; u = (53 high bits) / 2^53 in [0, 1), drawn in the order incident,
/// replicate, component (x, y, theta): the same seed gives the same samples bit for bit on any
/// platform. Output order: incident-major (all replicates of incident 0 first).
std::vector<Vel3> sample_reflected(const DiagonalModel& model, std::span<const Vel3> vin,
                                   std::size_t replicates, std::uint64_t seed);

/// Measured vs predicted reflected velocities, per component: two-sample Kolmogorov-Smirnov
/// statistic and p-value (stats::ks_two_sample).
struct DistributionComparison {
  std::array<stats::KsResult, 3> ks{};
  std::size_t n_measured = 0, n_predicted = 0;
};
DistributionComparison compare_distributions(std::span<const Vel3> measured,
                                             std::span<const Vel3> predicted);

/// Incident / reflected velocities of a set as vectors of Vel3 (set order).
std::vector<Vel3> incident(const ImpactSet& set);
std::vector<Vel3> reflected(const ImpactSet& set);
/// One component of a list of velocities.
std::vector<double> component(std::span<const Vel3> v, int c);

/// A fitted model as stored in HDF5 (`transfer fit --out FIT.h5`, read by `transfer predict
/// --model`): group /transfer with datasets A, dA (3), M, M_se (3x3) and attributes schema =
/// "ricochet-transfer-1", source, where, n.
struct StoredModel {
  DiagonalModel diagonal;
  Mat3 full{}, full_se{};
  bool has_full = false;
  std::string source, where;
  std::size_t n = 0;
};
void write_model_h5(const StoredModel& model, const std::string& path);
/// Throws InputError naming the file and the missing dataset when it is not a transfer model.
StoredModel read_model_h5(const std::string& path);

}  // namespace ricochet::transfer
