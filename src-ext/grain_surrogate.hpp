// The kriging pieces that the grain calibration's surrogates share (grain_calibration.hpp): the
// V_out components, the solid fraction (grain_packing.hpp) and the rebound indicator
// (rebound_region.hpp) are each one kriging over the grain parameters scaled to [0, 1].
//
// Model (Santner, Williams and Notz 2003, ch. 3; OpenTURNS KrigingAlgorithm): a constant trend, a
// Matern 5/2 covariance with scales bounded to [0.02, 2] in unit coordinates, and an optional
// homoscedastic noise (a nugget) for replicated means.
#pragma once

#include <array>
#include <openturns/OT.hxx>
#include <string>
#include <vector>

namespace ricochet::dem {

/// A grain parameter's recorded value (text, as the campaign index keeps it) as a number. Throws
/// InputError naming `file` and the parameter `name` when it is not one.
double grain_value(const std::string& text, const std::string& file, const std::string& name);

/// Kriging of y (n x 1) over u (n x d, unit coordinates), with noise variance `noise_var` per
/// point (0: interpolating). With `fixed`, that covariance model as is (no likelihood fit).
OT::KrigingResult fit_kriging(const OT::Sample& u, const OT::Sample& y, double noise_var,
                              const OT::CovarianceModel* fixed);

/// Leave-one-out check of a kriging fitted to (u, y) with covariance `cov` (the full fit's
/// parameters, not refitted): each point predicted by the others, into `loo`; returns
/// {Q2 = 1 - PRESS / sum (y - mean y)^2, RMSE}.
std::array<double, 2> leave_one_out(const OT::Sample& u, const OT::Sample& y, double noise,
                                    const OT::CovarianceModel& cov, std::vector<double>& loo);

}  // namespace ricochet::dem
