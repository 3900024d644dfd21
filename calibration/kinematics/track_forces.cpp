// track_with_forces (track_forces.hpp): local quadratic fits, Savitzky & Golay (1964).
#include "kinematics/track_forces.hpp"
#include "common/nan.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ricochet::kinematics {
namespace {

// First frame of the 2k + 1 frames fitted around frame i: centred, shifted inward at the ends.
std::size_t window_start(std::size_t i, std::size_t n, std::size_t k) {
  const std::size_t width = 2 * k + 1;
  return std::min(i > k ? i - k : 0, n - width);
}

/// Value, slope and curvature (second derivative) at t_i, and the unit-noise standard
/// deviations of slope and curvature.
struct LocalFit {
  double value = kNaN, slope = kNaN, curvature = kNaN;
  double slope_sd_unit = kNaN, curvature_sd_unit = kNaN;
};

LocalFit local_quadratic(const std::vector<double>& t, const std::vector<double>& v, std::size_t i,
                         std::size_t k) {
  const std::size_t a = window_start(i, t.size(), k), width = 2 * k + 1;
  // tau = (t - t_i) / scale keeps X^T X well conditioned at millisecond frame intervals.
  const double scale = std::max(std::abs(t[a] - t[i]), std::abs(t[a + width - 1] - t[i]));
  Eigen::MatrixXd X(static_cast<Eigen::Index>(width), 3);
  Eigen::VectorXd b(static_cast<Eigen::Index>(width));
  for (std::size_t r = 0; r < width; ++r) {
    const double tau = (t[a + r] - t[i]) / scale;
    const auto row = static_cast<Eigen::Index>(r);
    X(row, 0) = 1;
    X(row, 1) = tau;
    X(row, 2) = tau * tau;
    b[row] = v[a + r];
  }
  const Eigen::Matrix3d cov_unit = (X.transpose() * X).inverse();
  const Eigen::Vector3d c = cov_unit * (X.transpose() * b);
  LocalFit f;
  f.value = c[0];
  f.slope = c[1] / scale;
  f.curvature = 2 * c[2] / (scale * scale);
  f.slope_sd_unit = std::sqrt(cov_unit(1, 1)) / scale;
  f.curvature_sd_unit = 2 * std::sqrt(cov_unit(2, 2)) / (scale * scale);
  return f;
}

double positive_or_nan(double s) {
  return std::isfinite(s) && s > 0 ? s : kNaN;
}

}  // namespace

double smoothing_span_s(const Track& track, std::size_t i, std::size_t half_window) {
  const std::size_t a = window_start(i, track.t.size(), half_window);
  return track.t[a + 2 * half_window] - track.t[a];
}

BlockTrack track_with_forces(const Track& track, double sigma_position_m, double sigma_theta_rad,
                             const TrackForceOptions& o) {
  const std::size_t n = track.t.size(), k = o.half_window;
  const bool has_theta = !track.theta.empty();
  if (!(std::isfinite(o.mass_kg) && o.mass_kg > 0))
    throw std::invalid_argument("track forces: the block mass must be > 0 kg");
  if (has_theta && !(std::isfinite(o.inertia_kgm2) && o.inertia_kgm2 > 0))
    throw std::invalid_argument("track forces: the moment of inertia must be > 0 kg m^2");
  if (k < 1) throw std::invalid_argument("track forces: the half window must be at least 1 frame");
  if (n < 2 * k + 1)
    throw std::invalid_argument("track forces: " + std::to_string(n) + " frames, fewer than the " +
                                std::to_string(2 * k + 1) + " of one local fit");
  if (track.x.size() != n || track.y.size() != n || (has_theta && track.theta.size() != n))
    throw std::invalid_argument("track forces: the columns are not as long as t");
  for (std::size_t i = 1; i < n; ++i)
    if (!(track.t[i] > track.t[i - 1]))
      throw std::invalid_argument("track forces: time must increase");

  const double sp = positive_or_nan(sigma_position_m), st = positive_or_nan(sigma_theta_rad);
  BlockTrack out;
  out.block_mass_kg = o.mass_kg;
  out.t = track.t;
  for (std::size_t i = 0; i < n; ++i) {
    const LocalFit fx = local_quadratic(track.t, track.x, i, k);
    const LocalFit fy = local_quadratic(track.t, track.y, i, k);
    const LocalFit ft = has_theta ? local_quadratic(track.t, track.theta, i, k) : LocalFit{};
    out.x.push_back(fx.value);
    out.y.push_back(fy.value);
    out.theta.push_back(ft.value);
    out.vx.push_back(fx.slope);
    out.vy.push_back(fy.slope);
    out.w.push_back(ft.slope);
    out.fcx.push_back(o.mass_kg * fx.curvature);
    out.fcy.push_back(o.mass_kg * (fy.curvature + o.gravity_mps2));
    out.torque.push_back(has_theta ? o.inertia_kgm2 * ft.curvature : kNaN);
    out.sigma_fcx.push_back(o.mass_kg * sp * fx.curvature_sd_unit);
    out.sigma_fcy.push_back(o.mass_kg * sp * fy.curvature_sd_unit);
    out.sigma_torque.push_back(has_theta ? o.inertia_kgm2 * st * ft.curvature_sd_unit : kNaN);
    out.penetration.push_back(o.depth_below_centroid_m && has_theta
                                  ? o.depth_below_centroid_m(ft.value) - (fy.value - o.surface_y_m)
                                  : kNaN);
    const double spin = has_theta ? ft.slope : 0.0;
    out.ke_block.push_back(0.5 * o.mass_kg * (fx.slope * fx.slope + fy.slope * fy.slope) +
                           (has_theta ? 0.5 * o.inertia_kgm2 * spin * spin : 0.0));
  }
  out.pad();
  return out;
}

}  // namespace ricochet::kinematics
