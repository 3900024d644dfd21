// Trajectory reconstruction (paper section 2.3, Figs. 7-8): from tracked points of a block to
// its incident and reflected velocities, the same way for lab videos and LIGGGHTS time series.
//
// Model (paper section 2.3): outside the contact window the block is in free flight, so
//   x(t) = x0 + vx (t - t_e),                       (linear)
//   theta(t) = theta0 + omega (t - t_e),            (linear)
//   y(t) = y0 + vy (t - t_e) - g (t - t_e)^2 / 2     (quadratic, g imposed or fitted),
// fitted by least squares separately before and after the window and evaluated (value of the
// derivative) at the window's ends t_e = contact_start_s (V_in) and t_e = contact_end_s (V_out).
// The automatic window detection is documented in docs/commands/reconstruct.md.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "impact/impact_set.hpp"

namespace ricochet::kinematics {

/// A tracked trajectory in metres and seconds: the block centre (x, y) and the rotation angle
/// theta [rad, counter-clockwise positive, unwrapped]. From video tracks theta comes from the
/// eccentric mark: theta = atan2(mark_y - y, mark_x - x), unwrapped.
/// Frame: x horizontal, y up (paper Fig. 1); t strictly increasing.
struct Track {
  std::vector<double> t, x, y, theta;
  /// Position uncertainty of one tracked point [m] (e.g. pixel size / sqrt(12)); used for the
  /// standard errors. 0 = estimate from the fit residuals.
  double sigma_position_m = 0;
  /// Uncertainty of one theta value [rad]. 0 = sqrt(2) sigma_position_m / mark_radius_m when
  /// both are known (centre and mark pointed independently), else from the fit residuals.
  double sigma_theta_rad = 0;
  /// Distance between the centre and the eccentric mark [m] (median over the track); 0 when
  /// theta was given directly.
  double mark_radius_m = 0;
  /// Quantisation step of the positions [m] (the pixel size of a video track, 0 if none): the
  /// detection's noise estimate never goes below resolution / sqrt(12).
  double resolution_m = 0;
  std::string source;  ///< file name or description, for messages
};

/// Reads a track CSV: optional '#' comment lines, a header of `name[unit]` cells, one row per
/// frame. Required columns: t (s or ms), x and y (px, mm or m) and either mark_x and mark_y
/// (same units as x, y) or theta (rad or deg). Other columns are ignored. Columns in px need
/// `pixel_size_m` [m/px] (and a track in mm or m refuses it). `image_y_down` = true negates
/// y and mark_y (image coordinates grow downwards; Ricochet's y is up).
/// Throws InputError with file, line, column on malformed input: missing column or unit,
/// unknown unit, non-numeric or non-finite cell, wrong number of cells, non-increasing time,
/// px without pixel size, fewer than 6 rows.
Track read_track_csv(const std::string& path, std::optional<double> pixel_size_m,
                     bool image_y_down = false);
/// Same from CSV text; `name` is used in error messages.
Track parse_track_csv(const std::string& text, const std::string& name,
                      std::optional<double> pixel_size_m, bool image_y_down = false);

struct ReconstructOptions {
  /// Contact window [t_start, t_end] in s. When absent it is detected automatically (see
  /// docs/commands/reconstruct.md for the criterion). Give both or neither.
  std::optional<double> contact_start_s, contact_end_s;
  /// Gravity [m/s^2] imposed in the quadratic y(t) fit; absent = free quadratic coefficient.
  std::optional<double> gravity_mps2 = 9.81;
  /// Ground level [m] and the block's contact radius [m] used by the automatic detection: when
  /// both are given, contact is y <= ground_y_m + contact_radius_m (the paper's geometric
  /// criterion, Fig. 8b) and the window ends are where the free-flight fits cross that level.
  std::optional<double> ground_y_m;
  std::optional<double> contact_radius_m;
  /// Data-driven detection (no ground level): each free-flight window ends at the minimum of the
  /// cost sum_j (z_j^2 - k^2), z_j the standardised one-step prediction residual of point j
  /// (x, y and theta pooled): a point is free flight when explained within k standard deviations.
  double detection_k_sigma = 3.0;
  /// Points removed from each detected free-flight window on its contact side, so that frames in
  /// an undetectably gentle beginning (or end) of contact do not bias the fits.
  std::size_t detection_guard_points = 2;
  /// Points that seed each ballistic window (0 = automatic: 5, or 6 with free gravity).
  std::size_t detection_seed_points = 0;
};

struct Reconstruction {
  Vel3 vin{}, vout{};              ///< velocities at the window ends (m/s, m/s, rad/s)
  Vel3 sigma_vin{}, sigma_vout{};  ///< their standard errors
  /// Fitted positions (x [m], y [m], theta [rad]) at the window ends: with vin / vout and the
  /// gravity below they give the fitted free-flight curves (e.g. to draw paper Fig. 8).
  Vel3 position_in{}, position_out{};
  double contact_start_s = 0, contact_end_s = 0;
  bool window_detected = false;  ///< true when the window was detected automatically
  std::size_t points_before = 0, points_after = 0;
  /// How the window was set: "given", "ballistic-residuals" or "ground-level".
  std::string window_method;
  /// Points inside the detected free-flight windows whose prediction residual exceeded the
  /// threshold (isolated tracking outliers; kept in the fits).
  std::size_t flagged_points = 0;
  /// Gravity used before / after [m/s^2]: imposed, or fitted (-2 x quadratic coefficient) with
  /// its standard error (0 when imposed).
  double gravity_before_mps2 = 0, gravity_after_mps2 = 0;
  double sigma_gravity_before_mps2 = 0, sigma_gravity_after_mps2 = 0;
  /// Noise levels behind the standard errors [m], [rad], and where they come from: "given"
  /// (Track::sigma_*) or "residuals" (pooled residuals of the before and after fits).
  double sigma_position_m = 0, sigma_theta_rad = 0;
  std::string sigma_source;
  /// Root-mean-square residuals of the position fits (x and y pooled) [m], before and after.
  double rms_residual_before_m = 0, rms_residual_after_m = 0;
};

/// Linear fits of x(t), theta(t) and a quadratic fit of y(t) before and after the contact window,
/// evaluated at the window's ends. Throws std::invalid_argument when fewer than 3 points lie on
/// either side of the window, when the track is inconsistent (sizes, non-increasing time) or when
/// the detection finds no contact.
Reconstruction reconstruct(const Track& track, const ReconstructOptions& options = {});

/// The reconstructed release in the impact-set schema: `id`, `shape`, V_in and V_out with their
/// standard errors as the sigma columns, and the contact duration [s] (end - start of the
/// window); nothing else is set. `ricochet reconstruct` and the resolved model's extraction both
/// write their releases from it.
Impact to_impact(const Reconstruction& r, std::string id, std::string shape);

}  // namespace ricochet::kinematics
