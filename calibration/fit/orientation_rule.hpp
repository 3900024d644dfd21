// The orientation rules of blocks whose incidence angle is unknown (fit::AlphaMode::kMarginal,
// issue 35): the points over which a prediction, and the error a fit minimises, are averaged.
//
// A rule of n points divides the window [min_rad, max_rad) (one symmetry period) into n equal
// cells and takes one point per cell at the same fraction r of every cell:
//   alpha_k = min + (max - min) (k + r) / n,   k = 0 .. n-1.
// r = 1/2 is the midpoint rule. With `AlphaOptions::rotate`, r is drawn per release from its id
// (FNV-1a, below): the rule is then a randomly shifted lattice, whose mean over the releases is
// unbiased, and whose errors do not line up across releases (with the same midpoints for every
// release, a contact-sequence switch that the grid straddles biased every release alike: the lab
// triangles' held-out error moved from 0.986 to 0.907 between 3 and 6 points, docs/performance.md).
// The shift depends on the release only, never on the data's values, so held-out predictions stay
// leak-free, and a run is reproducible bit for bit.
//
// Quadrature error: the even- and odd-numbered points of a rule of even n are two interleaved rules
// of n/2 points (shifts r/2 and (r+1)/2). The larger difference of the full rule's mean from
// either half's is its error estimate: for an integrand with jumps (a switch of the contact
// sequence) the midpoint-type rule converges as 1/n, so the half rule's error, about twice the
// full rule's, is about that difference; the estimate is conservative for a smooth integrand
// (Davis & Rabinowitz 1984, Methods of Numerical Integration, section 2.9 on periodic integrands
// and section 4.4 on error estimates by comparing rules).
#pragma once

#include <array>
#include <string_view>
#include <vector>

namespace ricochet::fit {

struct AlphaOptions;

/// The per-release shift r in [0, 1) of `id`: FNV-1a 64-bit of its bytes scaled to [0, 1)
/// (Fowler, Noll & Vo; the constants of the public-domain reference).
double release_rotation(std::string_view id);

/// The n orientations [rad] of a rule over the window of `alpha` with shift r (file comment).
std::vector<double> orientation_rule(const AlphaOptions& alpha, int n, double r);

/// Means over a rule's points, with those of its two interleaved halves (file comment).
/// `values[k]` is the integrand at point k. For odd n the halves are the full rule (error 0).
struct RuleMean {
  double mean = 0;                  ///< over every point
  double mean_sq = 0;               ///< mean of the squares (for the spread)
  std::array<double, 2> half{};     ///< over the even- and the odd-numbered points
  std::array<double, 2> half_sq{};  ///< their means of the squares
  /// max_h |half[h] - mean|: the quadrature error estimate of `mean`.
  double error() const;
};
RuleMean rule_mean(const std::vector<double>& values);

}  // namespace ricochet::fit
