// The calibration error of one release: paper Eq. 7 (Garcia et al. 2020, section 4.2).
//
//   Err = sum_k ((V_k^simu - V_k^meas) / d_k)^2,   k in {vx, vy, omega},
//   d_k = max(|V_k^meas|, floor_k)
//
// The paper divides by the measured value itself (d_k = V_k^meas). A measured component close to
// zero (a block leaving almost without spin, omega_out = 2.41 rad/s for triangle T18) would make
// its term explode and dominate the fit, so the denominator is floored at `floor_k`: below the
// floor the term is an absolute difference scaled by the floor. The default floors (0.1 m/s,
// 0.1 m/s, 1 rad/s) are of the order of the measurement uncertainty and leave every lab release
// of Appendix A untouched (smallest |V_out| components: 0.18 m/s, 0.24 m/s, 2.41 rad/s), so on the
// lab data this is exactly the paper's Eq. 7.
#pragma once

#include <array>

#include "impact/impact_set.hpp"

namespace ricochet::fit {

/// Options of Eq. 7.
struct ErrorOptions {
  /// Smallest denominator per component {m/s, m/s, rad/s}; see the file comment.
  Vel3 floor = {0.1, 0.1, 1.0};
  /// Optional contact terms (not in the paper; used by the diagnosis, docs/diagnosis.md). When
  /// on, and the impact has the feature, the error gains
  ///   ((h^sim - h^meas) / d_h)^2      (maximum penetration h [m])
  ///   ((T^sim - T^meas) / d_T)^2      (contact duration T [s])
  /// so that effects that change the contact but hardly V_out (a stiffness law) are calibrated
  /// too. Off by default: exactly Eq. 7. The denominators (contact_error_scale()):
  ///   d_h = penetration_scale_m               when it is set (> 0): ONE constant for the set,
  ///   d_h = max(h^meas, penetration_floor_m)  otherwise (per release),
  /// and the same for T with contact_duration_scale_s, contact_duration_floor_s.
  /// Why a constant, unlike Eq. 7's per-release |V^meas|: the measured penetration carries
  /// noise of the order of its value (0.5 mm on 1.6 mm for the lab cylinder), and a release
  /// whose noise went up divides by a larger d_h and is weighted down, one whose noise went
  /// down is weighted up. The fit then follows the low readings: kn, which the contact terms
  /// identify, came out +18 % high on average (5 sets of an independent simulator, truth
  /// 3e7 N/m; docs/diagnosis.md, "Which stiffnesses the contact features identify"). A
  /// denominator that does not depend on the release's own reading weights every release
  /// alike. with_contact_terms() (fit/fit.hpp) sets the two scales to the set's mean measured
  /// value, floored by the floors below: the one rule of every caller (diagnosis, `ricochet
  /// calibrate`, contact_noise_threshold()). The velocity terms stay exactly Eq. 7.
  bool penetration = false;
  bool contact_duration = false;
  double penetration_floor_m = 0.5e-3;
  double contact_duration_floor_s = 1e-3;
  /// The constant denominators d_h [m] and d_T [s] (0: the per-release rule above).
  double penetration_scale_m = 0;
  double contact_duration_scale_s = 0;
};

/// Denominators d_k of Eq. 7 for a measured reflected velocity.
Vel3 error_scale(const Vel3& measured, const ErrorOptions& options = {});

/// Paper Eq. 7 for one release: sum of squared relative differences of the three reflected
/// velocity components (dimensionless). `simulated` and `measured` in (m/s, m/s, rad/s).
double release_error(const Vel3& simulated, const Vel3& measured, const ErrorOptions& options = {});

/// The three terms of Eq. 7 separately (vx, vy, omega), for diagnostics.
Vel3 release_error_terms(const Vel3& simulated, const Vel3& measured,
                         const ErrorOptions& options = {});

/// The denominators {d_h [m], d_T [s]} of the contact terms of one release (ErrorOptions: the
/// constant scale when set, else the floored measured value; 1 for a feature the impact
/// lacks). The one definition: contact_error_terms(), contact_noise_threshold() and the
/// diagnosis's per-observable scales all read it.
std::array<double, 2> contact_error_scale(const Impact& impact, const ErrorOptions& options);

/// The optional contact terms {penetration, contact duration} of one release (ErrorOptions);
/// 0 for a term that is off or whose feature the impact lacks. Simulated values in m and s.
std::array<double, 2> contact_error_terms(double penetration_sim_m, double contact_duration_sim_s,
                                          const Impact& impact, const ErrorOptions& options);

/// Expected value of Eq. 7 at the TRUE parameters caused by measurement noise alone:
///   Delta = sum_k (sigma_k / d_k)^2
/// with sigma_k the standard uncertainty of the measured component (first order, independent
/// errors). Parameter values whose re-optimised Eq. 7 stays within Delta of the optimum fit the
/// release as well as the truth would be expected to: they are the near-optimal set used for
/// identifiability (fit/fit.hpp).
double noise_threshold(const Vel3& measured, const Vel3& sigma, const ErrorOptions& options = {});

/// The contact terms' share of Delta: (sigma_h / d_h)^2 + (sigma_T / d_T)^2, d from
/// contact_error_scale(), for each term that `options` turns on and the impact has; 0 otherwise.
/// sigma_h [m], sigma_T [s]: standard uncertainties of the measured penetration and duration.
double contact_noise_threshold(const Impact& impact, double sigma_penetration_m,
                               double sigma_contact_duration_s, const ErrorOptions& options);

}  // namespace ricochet::fit
