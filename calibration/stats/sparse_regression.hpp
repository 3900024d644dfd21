// Sparse regression with the terms and their number chosen by leak-free cross-validation over
// groups, and bootstrap intervals over groups (issue 33, item 2: the force-residual diagnosis
// finds the few terms of a dimensioned library that explain the residual contact force; a group
// is a release, whose time samples are not independent of each other).
//
// Selection is best subset (Hastie, Tibshirani & Friedman 2009, sec. 3.3.1): every subset of
// the library's terms is fitted by least squares (no intercept: every term is neutral at zero,
// and so is the residual without missing physics) and scored by its K-fold cross-validated error
// over groups: each fold's fit sees only its training groups, so a group never influences its
// own held-out prediction. The error of a subset is the mean over groups of the group's mean
// squared held-out error. Per size k the best subset is kept; the size chosen is the smallest
// whose best subset is within one standard error of the best of all sizes (the one-standard-
// error rule, ibid. sec. 7.10), size 0 (nothing found) included. Exhaustive search is affordable
// for the small libraries of one force component (2^p subsets, p <= kMaxTerms).
// Sequentially thresholded least squares (STLSQ / SINDy, Brunton et al. 2016, PNAS 113:3932), the
// usual choice for large libraries, was tried first and dropped: penetration powers h, h^1.5,
// h^2 are collinear along a contact, and STLSQ kept a pair of them with large offsetting
// coefficients, whose standardised sizes exceed the true term's, at every threshold (2 of 5
// exact supports on the Katsuragi-Durian case of tests/diagnosis/force_law_test.cpp, also with
// a ridge); best subset found it in 5 of 5.
//
// A fixed support (SparseOptions::support: a law whose terms the user names) skips the
// selection: that subset alone is fitted, cross-validated and bootstrapped (beside the empty
// model's cross-validated error, for reference), so that the same folds and intervals judge a
// named law and a discovered one.
//
// The bootstrap resamples groups with replacement (Davison & Hinkley 1997, sec. 3.8, the
// cluster bootstrap) and answers two questions apart. How stable is the selection: in each
// resample the best subset of the chosen size is selected again (by its in-sample error), and a
// term's inclusion frequency is how often it is in it. How well known are the chosen law's
// constants: in each resample the chosen subset is refitted, and each of its terms gets the
// percentile interval of its coefficient; a term outside the law gets none. (Until 2026-12-07
// the interval was of the reselected fits with 0 where a term was not reselected: an interval
// of the selection and the constant at once, which printed [0, 0] for a term selected in few
// resamples and could leave the estimate outside its own interval. The bagged coefficients of
// ensemble SINDy, Fasel et al. 2022, Proc. R. Soc. A 478:20210904, mix the two the same way.)
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
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

/// The largest library sparse_regression() searches exhaustively.
inline constexpr std::size_t kMaxTerms = 14;

struct SparseOptions {
  std::size_t folds = 5;        ///< cross-validation folds over groups (at most the groups)
  std::size_t bootstrap = 200;  ///< group resamples for the intervals; 0: none
  double level = 0.95;          ///< of the percentile intervals
  std::uint64_t seed = 1;       ///< fold assignment and bootstrap draws
  /// A named law: this subset (bit mask over the columns) is fitted without selection (file
  /// comment); nullopt: the best subset is selected.
  std::optional<std::uint32_t> support;

  static constexpr OptionRange kFolds{2, 1000};
  static constexpr OptionRange kBootstrap{0, 1e6};
  static constexpr OptionRange kLevel{0, 1, true, true};
  /// The problems of these options (common/option_problems.hpp), empty when valid;
  /// sparse_regression() calls it at its entry.
  OptionProblems problems() const;
};

/// Least squares of y on the terms in `support` (a bit mask over the columns), on the samples
/// `rows` (all when empty). Returns the coefficients in the terms' own units, zero outside the
/// support (minimum-norm where the support's columns are collinear on these samples).
std::vector<double> subset_fit(const SparseDesign& d, std::uint32_t support,
                               std::span<const std::size_t> rows = {});

/// The prediction of every sample by the fit of `support` on the folds that do not hold its
/// group (leak-free: a sample's group never enters the fit of its own prediction).
/// `fold_of_group[g]` is the fold of the g-th distinct group in order of first appearance.
std::vector<double> heldout_predictions(const SparseDesign& d, std::uint32_t support,
                                        std::span<const std::size_t> fold_of_group);

struct SparseResult {
  std::vector<double> coef;  ///< the chosen subset's fit on all the data, in the terms' units
  std::vector<bool> active;  ///< the chosen subset
  std::size_t size = 0;      ///< its number of terms (0: nothing found)
  /// Per size k = 0..cols: the best subset's cross-validated error and its standard error.
  std::vector<double> cv_error, cv_se;
  std::vector<std::uint32_t> best_support;  ///< per size, the best subset (bit mask)
  std::vector<double> heldout;  ///< each sample's held-out prediction by the chosen subset
  /// Bootstrap percentile interval of each chosen term's coefficient, the chosen subset refitted
  /// on every resample (NaN for a term outside it, and without a bootstrap).
  std::vector<double> lo, hi;
  std::vector<double> inclusion;  ///< bootstrap frequency of each term in the reselected subset
  std::size_t groups = 0, folds = 0;
};

/// The whole procedure of the file comment. Throws InputError (field named) for a design whose
/// sizes disagree, non-finite values, more than kMaxTerms terms, fewer than two groups, a
/// support naming a column the design lacks, or bad options.
SparseResult sparse_regression(const SparseDesign& d, const SparseOptions& o = {});

}  // namespace ricochet::stats
