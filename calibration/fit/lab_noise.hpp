// The lab's measurement uncertainties: the one place these numbers are written. The calibration's
// identifiability threshold (fit::FitOptions), the diagnosis's noise floor when a set declares
// none (diagnosis::AssessOptions) and the synthetic sets' noise (diagnosis::NoiseSpec::lab())
// all read them from here.
#pragma once

#include "impact/impact_set.hpp"

namespace ricochet::fit {

/// Standard uncertainties (one standard deviation) of the lab's measurements, SI units.
struct LabNoise {
  /// V_in and V_out (m/s, m/s, rad/s): the differences between the two operators' means in
  /// paper Table 1, the paper's own estimate of the pointing error.
  static constexpr Vel3 vin = {0.1, 0.1, 1.4};
  static constexpr Vel3 vout = {0.1, 0.1, 3.4};
  /// Maximum penetration [m]: the pixel size, 0.5 mm. Our estimate: the paper measured none.
  static constexpr double penetration_m = 0.5e-3;
  /// Contact duration [s]: the 400 frames/s camera (paper section 2.1), start and end each read
  /// to one frame, 1 ms. Our estimate: the paper measured none.
  static constexpr double contact_duration_s = 1e-3;
};

}  // namespace ricochet::fit
