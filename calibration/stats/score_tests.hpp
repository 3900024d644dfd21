// Robust score tests of many hypotheses on the same independent units, with the family-wise error
// controlled by the step-down max-T adjustment (issue 10: the diagnosis's candidate test).
//
// Each hypothesis h (a candidate effect) owns one or more columns c (its added parameters). A
// column holds one score contribution per unit i (a release): u_ic = g_ic^T W r_i, the change
// the parameter makes to the release's predictions (projected off the base parameters'
// directions) dotted with the release's residual. Under H0 (the parameter is not needed) the
// score S_c = sum_i u_ic has mean zero; releases are independent, so its variance is estimated
// robustly, whatever the residuals' per-release covariance (noise, ground scatter, unknown
// orientation), from the contributions themselves (White 1980, Econometrica 48:817; the robust
// Lagrange multiplier test, Wooldridge 1990, Econometric Theory 6:17), centred, so that under
// the alternative the signal does not inflate its own variance (uncentred, T <= sqrt(n): an
// engine-made 20-release set with a plugin effect had T = 2.57 uncentred, 3.18 centred):
//   T_c = S_c / sqrt(n sum_i (u_ic - mean_c)^2 / nu),   nu = n - q - 1
// (q nuisance parameters re-estimated, one degree of freedom for the centring): the one-sample
// t statistic of the contributions.
// A column is one-sided (the parameter's neutral value is a bound: only T_c > 0 is evidence)
// or two-sided (|T_c|). A hypothesis's statistic is the largest of its columns'.
//
// Family-wise error: the statistics are strongly correlated (e_n^2 laws in the approach speed
// and in the incidence angle, rate_restitution: the same direction in the data), so Holm's
// bound, which assumes the worst, pays for 45 hypotheses where the data hold a few. The joint
// null distribution is estimated instead by the Gaussian multiplier bootstrap (Chernozhukov,
// Chetverikov & Kato 2013, Ann. Statist. 41:2786) of the centred contributions: T*_c = w sum_i
// (u_ic - mean_c) xi_i / sqrt(sum_i (u_ic - mean_c)^2), xi_i ~ N(0, 1) shared by all columns (so
// the draws keep the scores' correlation), times w = sqrt(nu / chi2_nu) shared by all columns (a
// multivariate t with nu = n - q - 1 degrees of freedom, for the estimated variances: Hothorn,
// Bretz & Westfall 2008, Biometrical J. 50:346). Adjusted p-values are the step-down max-T of
// Westfall & Young (1993; Romano & Wolf 2005, JASA 100:94): with the statistics sorted H_(1) >=
// H_(2) >= ...,
//   p_adj(k) = max(p_adj(k-1), P*(max_{j >= k} H*_(j) >= H_(k))),
// which controls the family-wise error rate strongly. A hypothesis with no column (it could not
// be tested) has p = 1 and does not enter the maxima.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace ricochet::stats {

/// One column: a parameter's score contributions, one per unit.
struct ScoreColumn {
  std::size_t hypothesis = 0;  ///< index of the hypothesis it belongs to
  std::vector<double> u;       ///< per unit (all columns the same length n)
  bool two_sided = false;      ///< |T| (neutral value inside the bounds) or T (at a bound)
};

struct ScoreTestOptions {
  std::size_t nuisance = 0;  ///< q: parameters re-estimated under H0 (projected out)
  /// Level of the multiple comparisons with the best (ScoreTests::mcb_critical).
  double mcb_level = 0.05;
  std::size_t draws = 20000;      ///< multiplier bootstrap draws
  std::uint64_t seed = 20260401;  ///< of the draws (a run is reproducible bit for bit)
};

struct ScoreTests {
  std::vector<double> statistic;   ///< per hypothesis: max over its columns of T (or |T|)
  std::vector<double> p_value;     ///< per hypothesis, unadjusted (same bootstrap, alone)
  std::vector<double> p_adjusted;  ///< per hypothesis, step-down max-T (family-wise)
  std::vector<double> t;           ///< per column: T_c (signed)
  double dof = 0;                  ///< nu = n - q - 1
  /// The joint null's maximum over every hypothesis, one per draw, sorted ascending: the
  /// single-step max-T critical values (max_null_quantile).
  std::vector<double> max_null;
  /// Multiple comparisons with the best (MCB; Hsu 1984, Ann. Statist. 12:1136; Hsu 1996,
  /// "Multiple Comparisons", ch. 4), at level mcb_level, among the hypotheses and a reference
  /// whose statistic is 0 with no noise (the model with nothing added). Per hypothesis h, c_h is
  /// the 1 - level quantile of max_{k != h} (H*_k - H*_h), the reference's H* = 0 included; NaN
  /// for an untested hypothesis. h cannot be told apart from the best when
  ///   H_h >= max(0, max_{k != h} H_k) - c_h,
  /// and the set of such h holds the hypothesis of largest expected statistic with probability
  /// at least 1 - level (only the comparisons of that one hypothesis need to hold).
  std::vector<double> mcb_critical;
  /// The reference's own c: the 1 - level quantile of max(0, max_k H*_k). The reference is in the
  /// set when no statistic exceeds it (the single-step max-T test at that level).
  double mcb_reference_critical = NAN;
};

/// One column's contributions summed (the score S), their mean, and their centred sum of squares.
struct ColumnMoments {
  double sum = 0, mean = 0, ss = 0;
};
ColumnMoments column_moments(std::span<const double> u);
/// The score's robust standard error sqrt(n ss / nu) (file comment), nu the degrees of freedom
/// (ScoreTests::dof); what T_c divides S by. NaN when nu <= 0.
double score_standard_error(std::span<const double> u, double dof);

/// The (1 - level) quantile of the joint null's maximum: the critical value that a hypothesis's
/// statistic must exceed for its max-T adjusted p to fall below `level` at the first step of the
/// step-down (the power of the family-wise test is computed against it). NaN without draws.
double max_null_quantile(const ScoreTests& tests, double level);

/// The tests of `hypotheses` hypotheses from their columns (file comment). Throws
/// std::invalid_argument when columns differ in length, a column names a hypothesis out of
/// range, or n <= q + 1.
ScoreTests robust_score_tests(std::span<const ScoreColumn> columns, std::size_t hypotheses,
                              const ScoreTestOptions& options = {});

}  // namespace ricochet::stats
