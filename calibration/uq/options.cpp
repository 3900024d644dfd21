// The one check of each uq options struct (montecarlo.hpp, sobol.hpp).
#include "uq/montecarlo.hpp"
#include "uq/sobol.hpp"

namespace ricochet::uq {

OptionProblems MonteCarloOptions::problems() const {
  OptionProblems p;
  check_range(p, "runs", static_cast<double>(runs), kRuns);
  check_range(p, "alpha_min_rad", alpha_min_rad, kAlphaRad);
  check_range(p, "alpha_max_rad", alpha_max_rad, kAlphaRad);
  if (!(alpha_min_rad < alpha_max_rad))
    p.push_back({"alpha_max_rad", "must be above alpha_min_rad"});
  append_nested(p, "engine", engine.problems());
  return p;
}

OptionProblems RangeFitOptions::problems() const {
  OptionProblems p;
  append_nested(p, "mc", mc.problems());
  check_range(p, "max_evaluations", max_evaluations, kMaxEvaluations);
  check_range(p, "xtol", xtol, kXtol);
  return p;
}

OptionProblems SobolOptions::problems() const {
  OptionProblems p;
  check_range(p, "base_size", static_cast<double>(base_size), kBaseSize);
  check_range(p, "bootstrap", static_cast<double>(bootstrap), kBootstrap);
  check_range(p, "confidence", confidence, kConfidence);
  return p;
}

}  // namespace ricochet::uq
