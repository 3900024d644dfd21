// Contact force and torque from tracked accelerations: Newton's second law on a video (or any
// position-only) track, so that a lab's high-speed video gives the same time series as a
// LIGGGHTS campaign (impact/block_track.hpp) and the force-residual diagnosis reads both.
//
// Method (Savitzky & Golay 1964, local polynomial least squares): at each frame i, a quadratic
//   q(t) = c0 + c1 (t - t_i) + c2 (t - t_i)^2
// is fitted to the 2k + 1 frames around i (shifted inward at the ends of the track) for x, y and
// theta separately; the value, slope and curvature give position, velocity and acceleration at
// t_i. With m the block's mass, I its moment of inertia about the centroid and g gravity (y up):
//   fcx = m a_x,    fcy = m (a_y + g),    torque = I alpha          (Newton-Euler, 2-D)
// Standard errors from the fit's covariance, Cov(c) = sigma^2 (X^T X)^{-1}, with sigma the
// pointing noise of one tracked value (Reconstruction::sigma_position_m, sigma_theta_rad):
//   sd(fcx) = 2 m sigma sqrt([(X^T X)^{-1}]_22), and likewise for fcy and the torque.
// These are the noise terms only. The fit also smooths: the force at t_i is a weighted mean of
// the force over the window's span, 2 k frame intervals, so a force that changes within that
// span (the onset of contact) is blurred. That bias is not in the standard error; the span is
// the estimate's time resolution and is reported with it (docs/commands/reconstruct.md).
#pragma once

#include <cstddef>
#include <functional>
#include <limits>

#include "impact/block_track.hpp"
#include "kinematics/reconstruct.hpp"

namespace ricochet::kinematics {

struct TrackForceOptions {
  double mass_kg = std::numeric_limits<double>::quiet_NaN();       ///< block mass [kg], > 0
  double inertia_kgm2 = std::numeric_limits<double>::quiet_NaN();  ///< about the centroid [kg m^2]
  double gravity_mps2 = 9.81;                                      ///< [m/s^2], y up
  /// k: each local fit spans 2k + 1 frames (k >= 1).
  std::size_t half_window = 2;
  /// Level of the bed surface in the track's frame [m] (the paper measures y from it: 0).
  double surface_y_m = 0;
  /// Depth of the block's lowest point below its centroid at angle theta [m] (e.g.
  /// Shape::depth_below_centroid). Empty: the penetration column is NaN.
  std::function<double(double)> depth_below_centroid_m;
};

/// The track as a BlockTrack (the /dem/tracks schema): t as tracked; x, y, theta, vx, vy, w the
/// local fits' values and slopes; fcx, fcy, torque from the accelerations with their standard
/// errors in sigma_fcx, sigma_fcy, sigma_torque; penetration = depth_below_centroid(theta) -
/// (y - surface) when the depth function is given; ke_block from the fitted velocities;
/// block_mass_kg = mass. Without theta (track.theta empty) theta, w, torque and its sigma are
/// NaN. sigma_position_m and sigma_theta_rad are the per-value noise [m], [rad] (e.g. from
/// reconstruct()); NaN or <= 0 gives NaN standard errors.
/// Throws std::invalid_argument when the mass is not > 0, the inertia is not > 0 while theta is
/// tracked, k < 1, or the track has fewer than 2k + 1 frames (or 3).
BlockTrack track_with_forces(const Track& track, double sigma_position_m, double sigma_theta_rad,
                             const TrackForceOptions& options);

/// The time span of one local fit around frame i [s]: the estimate's time resolution.
double smoothing_span_s(const Track& track, std::size_t i, std::size_t half_window);

}  // namespace ricochet::kinematics
