// Issue 35, item 1: the lab triangles' orientation average has converged. Appendix A gives no
// orientation at contact, so every triangle prediction is an average over it (a search rule of 6
// orientations for the fits' multi-start, a polish rule of 24 for their best ends and for every
// prediction, each release's rules shifted by its id: fit/orientation_rule.hpp). Refining the
// polish rule to 48 must move the leak-free held-out error of the paper's law by less than 1 %
// (the rule), and the half-rule estimate of its quadrature error must be below 1 % of it.
// With one 6-point midpoint grid for fits and predictions the same error moved by 4 % between 6
// and 12 points (0.907, 0.941; docs/performance.md).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "diagnosis/assess.hpp"

namespace ricochet::diagnosis {
namespace {

TEST(OrientationConvergence, TheLabTrianglesHeldOutErrorHoldsWhenThePolishRuleIsRefined) {
  const ImpactSet set =
      read_impact_set(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/triangles.csv");
  const Shape shape = Shape::triangle();
  AssessOptions o;
  const Assessment a = assess(Model::paper(), shape, set, o);
  o.fit.alpha.polish_points = 48;
  const Assessment b = assess(Model::paper(), shape, set, o);
  const double e = a.heldout.error.mean, e48 = b.heldout.error.mean;
  EXPECT_LT(std::fabs(e48 - e), 0.01 * e) << "24 orientations: " << e << ", 48: " << e48;
  EXPECT_GT(a.heldout.quadrature_error, 0.0);
  EXPECT_LT(a.heldout.quadrature_error, 0.01 * e);
  EXPECT_LT(b.heldout.quadrature_error, 0.01 * e48);
}

}  // namespace
}  // namespace ricochet::diagnosis
