// The global search of a population fit whose releases are averaged over an orientation rule
// (issue 35, item 3), on a response surface instead of many local runs of the engine.
//
// Why: a multi-start on the engine (32 BOBYQA runs of about 37 evaluations each on a coarse
// orientation rule, then a polish of the best 3 ends on the refined rule) spends most of a
// triangle diagnosis's collisions picking among minima that are partly the coarse rule's
// quadrature noise (docs/performance.md). Here every collision is on the refined rule, and the
// search between them is on a cheap interpolant of the objective:
//
//   1. the start design (data-free: the model's own values and a Latin hypercube) is evaluated
//      on the refined rule;
//   2. each round fits a cubic radial basis function with a linear tail to every point
//      evaluated so far (Powell 1992; Gutmann 2001, J. Global Optim. 19:201), values above their
//      median replaced by the median so that failed rebounds do not make the surface ring
//      (Regis & Shoemaker 2007, INFORMS J. Comput. 19:497, section 3);
//   3. it minimises the surface from its best evaluated points (BOBYQA on the surface, no
//      collision) and evaluates the minimum, and, to explore, the surface's minimum at least
//      beta away from every evaluated point, beta cycling through `explore` (the CORS rule of
//      Regis & Shoemaker 2005, J. Global Optim. 31:153);
//   4. it stops when two rounds in a row the surface's minimum lies within `xtol` of a point
//      already evaluated (the surface predicts nothing better elsewhere), or after `rounds`.
//
// The best evaluated point is the answer; population.cpp then polishes it by BOBYQA on the
// engine. Each evaluated point is a true value of the objective, so the reported minimum is
// never the surface's.
#pragma once

#include <cstddef>
#include <vector>

#include "fit/optimize.hpp"

namespace ricochet::fit::detail {

/// s(u) = sum_i lambda_i |u - u_i|^3 + c_0 + sum_k c_k u_k, interpolating `values` at `points`
/// (row-major, `dim` per point; at least dim + 1 points not on one hyperplane). Throws
/// std::invalid_argument when the points cannot carry the linear tail.
class CubicRbf {
 public:
  CubicRbf(const std::vector<double>& points, std::size_t dim, const std::vector<double>& values);
  double operator()(const double* u) const;

 private:
  std::size_t dim_;
  std::vector<double> points_;
  std::vector<double> lambda_;
  std::vector<double> tail_;  ///< c_0, c_1 .. c_dim
};

struct SurrogateSearchOptions {
  int starts = 32;     ///< BOBYQA runs on the surface per round, from its best evaluated points
  int rounds = 24;     ///< rounds at most (each evaluates at most two points on the engine)
  double xtol = 0.01;  ///< a surface minimum this close (max-norm, unit box) is not new
  /// Exploration distances of the CORS point, cycled round by round (unit box, Euclidean);
  /// 0 skips the exploring point that round.
  std::vector<double> explore = {0.2, 0.1, 0.05, 0.0};
};

/// Minimises `problem` from `points` (row-major, problem.dim() per point) with their `values`
/// by the rounds of the file comment. `evaluated` receives every point evaluated, the design's
/// included, with its value. Returns the best of them.
LocalResult surrogate_search(Problem& problem, const std::vector<double>& points,
                             const std::vector<double>& values,
                             const SurrogateSearchOptions& options,
                             std::vector<LocalResult>& evaluated);

}  // namespace ricochet::fit::detail
