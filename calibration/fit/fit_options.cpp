// FitOptions::problems(): the one check of the calibration settings (fit.hpp).
#include "fit/fit.hpp"

namespace ricochet::fit {

OptionProblems FitOptions::problems() const {
  OptionProblems p;
  check_range(p, "starts", starts, kStarts);
  check_range(p, "design_points", design_points, kDesignPoints);
  check_range(p, "max_evaluations", max_evaluations, kMaxEvaluations);
  check_range(p, "xtol", xtol, kUnitFraction);
  check_range(p, "interval_resolution", interval_resolution, kUnitFraction);
  check_range(p, "alpha.marginal_points", alpha.marginal_points, kMarginalPoints);
  check_range(p, "alpha.polish_points", alpha.polish_points, kPolishPoints);
  if (alpha.polish_points == 1)
    p.push_back({"alpha.polish_points", "1 is no average: 0 (no polish) or at least 2"});
  check_range(p, "alpha.polish_ends", alpha.polish_ends, kPolishEnds);
  check_range(p, "alpha.surface_rounds", alpha.surface_rounds, kSurfaceRounds);
  check_range(p, "alpha.search_xtol", alpha.search_xtol, kUnitFraction);
  check_range(p, "alpha.min_rad", alpha.min_rad, kAlphaRad);
  check_range(p, "alpha.max_rad", alpha.max_rad, kAlphaRad);
  if (!(alpha.min_rad < alpha.max_rad))
    p.push_back({"alpha.max_rad", "must be above alpha.min_rad"});
  for (double s : sigma) check_range(p, "sigma", s, kSigma);
  check_range(p, "sigma_penetration_m", sigma_penetration_m, kSigma);
  check_range(p, "sigma_contact_duration_s", sigma_contact_duration_s, kSigma);
  check_range(p, "threshold_scale", threshold_scale, kThresholdScale);
  append_nested(p, "engine", engine.problems());
  return p;
}

}  // namespace ricochet::fit
