// Trajectory reconstruction (paper section 2.3, Figs. 7-8): from tracked points of a block to
// its incident and reflected velocities, the same way for lab videos and LIGGGHTS time series.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "impact/impact_set.hpp"

namespace ricochet::kinematics {

/// A tracked trajectory in metres and seconds: the block centre (x, y) and the rotation angle
/// theta [rad, counter-clockwise positive, unwrapped]. From video tracks theta comes from the
/// eccentric mark: theta = atan2(mark_y - y, mark_x - x), unwrapped.
struct Track {
  std::vector<double> t, x, y, theta;
  /// Position uncertainty of one tracked point [m] (e.g. pixel size / sqrt(12)); used for the
  /// standard errors. 0 = estimate from the fit residuals.
  double sigma_position_m = 0;
};

/// Reads a track CSV: columns t[s], x, y, mark_x, mark_y with units px (then `pixel_size_m`
/// is required) or m. Throws InputError with file, line, column on malformed input.
Track read_track_csv(const std::string& path, std::optional<double> pixel_size_m);

struct ReconstructOptions {
  /// Contact window [t_start, t_end] in s. When absent it is detected automatically (see
  /// docs/commands/reconstruct.md for the criterion).
  std::optional<double> contact_start_s, contact_end_s;
  /// Gravity [m/s^2] imposed in the quadratic y(t) fit; absent = free quadratic coefficient.
  std::optional<double> gravity_mps2 = 9.81;
  /// Ground level [m] and the block's contact radius [m] used by the automatic detection.
  std::optional<double> ground_y_m;
};

struct Reconstruction {
  Vel3 vin{}, vout{};             ///< velocities at the window ends (m/s, m/s, rad/s)
  Vel3 sigma_vin{}, sigma_vout{}; ///< their standard errors
  double contact_start_s = 0, contact_end_s = 0;
  bool window_detected = false;   ///< true when the window was detected automatically
  std::size_t points_before = 0, points_after = 0;
};

/// Linear fits of x(t), theta(t) and a quadratic fit of y(t) before and after the contact window,
/// evaluated at the window's ends. Throws std::invalid_argument when fewer than 3 points lie on
/// either side of the window.
Reconstruction reconstruct(const Track& track, const ReconstructOptions& options = {});

}  // namespace ricochet::kinematics
