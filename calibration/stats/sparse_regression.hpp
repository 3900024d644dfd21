// Sparse regression with the support chosen by leak-free cross-validation over groups, and
// bootstrap intervals over groups (issue 33, item 2: the force-residual diagnosis finds the few
// terms of a dimensioned library that explain the residual contact force; a group is a release,
// whose time samples are not independent of each other).
//
// The fit is sequentially thresholded least squares, STLSQ (Brunton, Proctor & Kutz 2016, PNAS
// 113:3932, "SINDy"): least squares on all terms, then repeatedly zero every coefficient whose
// standardised size is below the threshold tau and refit on the others, until the support no
// longer changes. A coefficient's standardised size is its share of the response,
// |b_j| rms(x_j) / rms(y), rms over the training samples: dimensionless, so one tau serves terms
// of any unit, and a term whose contribution is a fraction tau of the response survives.
// There is no intercept: every term is neutral at zero, and so is the residual without missing
// physics.
//
// tau is chosen on a grid FIXED in advance (0, then log-spaced from tau_min to tau_max, then
// infinity, the empty model), not from the data, so that a held-out group never influences its
// own prediction, not even through the grid or the scaling: each fold scales and fits on its
// training groups alone. The cross-validated error of tau is the mean over groups of the group's
// mean squared held-out error; the chosen tau is the largest (sparsest) whose error is within one
// standard error of the smallest (the one-standard-error rule, Hastie, Tibshirani & Friedman
// 2009, sec. 7.10). The empty model is on the grid: when nothing beats it by a standard error,
// nothing is found.
//
// The bootstrap resamples groups with replacement (Davison & Hinkley 1997, sec. 3.8, the
// cluster bootstrap) and refits at the chosen tau: each term's inclusion frequency and the
// percentile interval of its coefficient (0 where it was not selected).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "common/option_problems.hpp"

namespace ricochet::stats {

/// A design: `rows` samples of `cols` terms, row-major (x[i * cols + j] is term j at sample i),
/// with the response y (one per sample) and the group of each sample (its release; any ids).
struct SparseDesign {
  std::span<const double> x;
  std::size_t cols = 0;
  std::span<const double> y;
  std::span<const std::size_t> group;
  std::size_t rows() const { return y.size(); }
};

struct SparseOptions {
  std::size_t folds = 5;               ///< cross-validation folds over groups (at most the groups)
  std::size_t grid = 25;               ///< log-spaced thresholds between tau_min and tau_max
  double tau_min = 1e-3, tau_max = 1;  ///< standardised sizes (file comment)
  std::size_t bootstrap = 200;         ///< group resamples for the intervals; 0: none
  double level = 0.95;                 ///< of the percentile intervals
  std::size_t max_iterations = 25;     ///< STLSQ refits before the support must be stable
  std::uint64_t seed = 1;              ///< fold assignment and bootstrap draws

  static constexpr OptionRange kFolds{2, 1000};
  static constexpr OptionRange kGrid{1, 1000};
  static constexpr OptionRange kTau{0, 1e3, true, false};
  static constexpr OptionRange kBootstrap{0, 1e6};
  static constexpr OptionRange kLevel{0, 1, true, true};
  static constexpr OptionRange kIterations{1, 1000};
  /// The problems of these options (common/option_problems.hpp), empty when valid; tau_min must
  /// be below tau_max. sparse_regression() calls it at its entry.
  OptionProblems problems() const;
};

/// One STLSQ fit at threshold tau (file comment) on the samples `rows` of the design (all when
/// empty). Returns the coefficients in the terms' own units (zero outside the support).
std::vector<double> stlsq(const SparseDesign& d, double tau, std::size_t max_iterations,
                          std::span<const std::size_t> rows = {});

/// The prediction of every sample by the fit at `tau` on the folds that do not hold its group
/// (leak-free: a sample's group enters neither the fit nor the scaling of its own prediction).
/// `fold_of_group[g]` is the fold of the g-th distinct group in order of first appearance.
std::vector<double> heldout_predictions(const SparseDesign& d, double tau,
                                        std::span<const std::size_t> fold_of_group,
                                        std::size_t max_iterations);

struct SparseResult {
  std::vector<double> coef;  ///< at the chosen tau, on all the data, in the terms' units
  std::vector<bool> active;  ///< coef != 0
  double tau = 0;            ///< chosen threshold (infinity: the empty model)
  std::vector<double> taus, cv_error, cv_se;  ///< the grid and its cross-validated errors
  double cv_error_empty = 0;                  ///< the empty model's (every prediction 0)
  std::vector<double> heldout;    ///< each sample's held-out prediction at the chosen tau
  std::vector<double> lo, hi;     ///< bootstrap percentile interval per term (NaN without one)
  std::vector<double> inclusion;  ///< bootstrap frequency of each term in the support
  std::size_t groups = 0, folds = 0;
};

/// The whole procedure of the file comment. Throws InputError (field named) for a design whose
/// sizes disagree, non-finite values, fewer than two groups, or bad options.
SparseResult sparse_regression(const SparseDesign& d, const SparseOptions& o = {});

}  // namespace ricochet::stats
