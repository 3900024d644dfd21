// T-optimal discrimination between rival models: the criterion, the predicted power, and the
// selection of a design (issue 31, item 3). The numbers only: no engine, no model. The design
// command (throw_design.hpp) fills the per-state terms from the rivals' predictions.
//
// Criterion (Atkinson & Fedorov 1975, Biometrika 62:57, the T-criterion, in its
// generalised-least-squares form): when rival a is the truth and rival b is refitted to data from
// the design xi, the noncentrality of b's lack of fit is
//   lambda_ab(xi) = min over delta of sum over states s in xi of
//                   | W D_s^-1 (f_a(s) - f_b(s) - J_b(s) delta) |^2,
// f_r(s) the prediction of rival r calibrated on the set, J_b(s) the Jacobian of b's predictions
// in its calibrated parameters (the refit linearised at b's calibration), D_s the error
// denominators of state s and W the whitening of the set's scaled residuals (signature.hpp,
// Directions::whiten). With r_s = W D_s^-1 (f_a - f_b) and G_s = W D_s^-1 J_b,
//   lambda_ab = C - g^T H^+ g,   C = sum r_s^T r_s,  g = sum G_s^T r_s,  H = sum G_s^T G_s
// (the least-squares residual in closed form): additive in the states through (C, g, H), so a
// state's contribution is three small sums (StateTerms).
//
// A pair's value is min(lambda_ab, lambda_ba) (symmetrised: the design must decide whichever of
// the two is true). Nested pairs are the exception: when b holds every effect of a and more,
// lambda_ab (the smaller law true, the larger refitted) is zero for an exact refit, since the
// larger law at its added effect's neutral value IS the smaller one; what the linearised refit
// leaves of it is linearisation error (lab cylinders, none vs en2_incidence_angle_linear, whose
// calibrated slope sits at its bound: 4.2 against 47 the other way), and as the minimum it would
// drive the design. For a nested pair only lambda_ba (the larger law true, the smaller refitted)
// counts: the one direction in which data can reject a law (Atkinson, Donev & Tobias 2007,
// Optimum Experimental Designs, with SAS, chapter 20: for nested models the T-criterion takes the
// larger model as the truth).
//
// Design (max-min over pairs): xi = the set's own states (fixed: the new throws are diagnosed
// together with the old ones) plus `budget` states chosen among the candidates, each at most
// once; greedy forward selection (each step adds the candidate that raises the smallest pair
// value most), then exchange passes (swap a chosen state for a candidate whenever that raises
// the criterion) until no swap improves it (the exchange algorithm of Fedorov 1972, Theory of
// Optimal Experiments, Academic Press, with the T-criterion in place of D). Ties go to the lowest
// index: the result depends only on the inputs.
//
// Power: the lack-of-fit statistic of one pair is taken as chi^2 with 1 degree of freedom,
// noncentral with lambda under the alternative (the design's question is one comparison, "a or
// b"); at level alpha
//   power = P(chi^2_1(lambda) > z^2) = Phi(sqrt(lambda) - z) + Phi(-sqrt(lambda) - z),
//   z = Phi^-1(1 - alpha / 2)
// (a noncentral chi^2_1 is the square of N(sqrt(lambda), 1)).
#pragma once

#include <Eigen/Dense>
#include <cstddef>
#include <span>
#include <vector>

namespace ricochet::diagnosis {

/// Largest number of calibrated parameters of a refitted rival (fixed-size algebra in the
/// selection's inner loop: the paper's three, kn, and two effects of two parameters).
inline constexpr int kMaxRivalParameters = 8;
using ParamVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxRivalParameters, 1>;
using ParamMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxRivalParameters,
                                  kMaxRivalParameters>;

/// One state's contribution to one direction (truth a, refitted b) of a pair (file comment):
/// c = r^T r, g = G^T r, h = G^T G.
struct StateTerms {
  double c = 0;
  ParamVector g;
  ParamMatrix h;
};

/// The terms of a state from its whitened difference r (f_a - f_b) and the whitened Jacobian G
/// of the refitted rival (rows: observables, columns: parameters).
StateTerms state_terms(const Eigen::VectorXd& r, const Eigen::MatrixXd& G);

/// Running sums of StateTerms over a design, and the noncentrality they give.
struct TermSum {
  double c = 0;
  ParamVector g;
  ParamMatrix h;
  explicit TermSum(int parameters = 0);
  void add(const StateTerms& t, double weight = 1.0);
  /// lambda = C - g^T H^+ g, never below 0. H^+: the inverse on H's numerically non-null
  /// eigenvectors (a parameter that does nothing on the design, mu in a sticking contact, is no
  /// refit direction).
  double lambda() const;
};

/// One direction of a pair: the terms of every state (the set's, then the candidates').
struct Direction {
  std::size_t truth = 0, fitted = 0;  ///< rival indices
  int parameters = 0;                 ///< of the refitted rival
  std::vector<StateTerms> states;
};

/// A pair's value is the minimum of its directions' lambdas (one direction for a nested pair).
struct PairRule {
  std::vector<std::size_t> directions;  ///< indices into the Direction list
};

/// lambda of one direction on the states `states` (indices into Direction::states).
double direction_lambda(const Direction& d, std::span<const std::size_t> states);

/// The noncentral chi^2_1 power at level alpha (file comment). lambda >= 0, alpha in (0, 1).
double discrimination_power(double lambda, double alpha);

struct SelectionOptions {
  std::size_t budget = 0;      ///< states to choose
  std::size_t max_passes = 0;  ///< exchange passes at most (0: greedy only; DesignOptions)
  /// A swap must raise the criterion by this fraction of it (rounding is no improvement).
  double relative_gain = 1e-12;
};

/// The max-min design (file comment). `fixed`: the states always in (the set's: 0..fixed-1);
/// candidates are states fixed..fixed+candidates-1 of every Direction.
struct Selection {
  std::vector<std::size_t> chosen;  ///< candidate state indices (>= fixed), in selection order
  double value = 0;                 ///< min over pairs of the pair value, at the end
  double greedy_value = 0;          ///< the same after the greedy stage
  std::size_t passes = 0;           ///< exchange passes run
  std::size_t swaps = 0;            ///< exchanges made
};
Selection select_max_min(const std::vector<Direction>& directions,
                         const std::vector<PairRule>& pairs, std::size_t fixed,
                         std::size_t candidates, const SelectionOptions& options);

}  // namespace ricochet::diagnosis
