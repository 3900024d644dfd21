// Trajectory reconstruction (paper section 2.3). See reconstruct.hpp for the model and
// docs/commands/reconstruct.md for the automatic contact-window criterion. The track CSV reader
// is track_csv.cpp.
#include "kinematics/reconstruct.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/nan.hpp"
#include "stats/median.hpp"

namespace ricochet::kinematics {
namespace {

// ---------------------------------------------------------------------------------------------
// Least squares

/// Polynomial least-squares fit v(t) = sum_k c_k tau^k - g (t - t_ref)^2 / 2, tau = (t - t_ref)
/// / scale, of degree 1 or 2 (g = 0 unless gravity is imposed on y). Centering at the
/// evaluation time and scaling keep the normal matrix well conditioned.
struct PolyFit {
  double t_ref = 0, scale = 1, g_imposed = 0;
  Eigen::VectorXd coef;
  Eigen::MatrixXd cov_unit;  // (X^T X)^-1: covariance of coef for unit noise
  double rss = 0;
  std::size_t n = 0;

  std::size_t params() const { return static_cast<std::size_t>(coef.size()); }
  Eigen::VectorXd basis(double t) const {
    Eigen::VectorXd phi(coef.size());
    const double tau = (t - t_ref) / scale;
    double p = 1;
    for (Eigen::Index k = 0; k < coef.size(); ++k, p *= tau) phi[k] = p;
    return phi;
  }
  Eigen::VectorXd basis_derivative(double t) const {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(coef.size());
    const double tau = (t - t_ref) / scale;
    double p = 1;
    for (Eigen::Index k = 1; k < coef.size(); ++k, p *= tau)
      d[k] = static_cast<double>(k) * p / scale;
    return d;
  }
  double value(double t) const {
    return basis(t).dot(coef) - 0.5 * g_imposed * (t - t_ref) * (t - t_ref);
  }
  double derivative(double t) const {
    return basis_derivative(t).dot(coef) - g_imposed * (t - t_ref);
  }
  /// Standard deviation of derivative(t) for unit noise.
  double derivative_sd_unit(double t) const {
    const Eigen::VectorXd d = basis_derivative(t);
    return std::sqrt(std::max(0.0, d.dot(cov_unit * d)));
  }
};

PolyFit fit_poly(const std::vector<double>& t, const std::vector<double>& v,
                 const std::vector<std::size_t>& idx, int degree, double t_ref, double g_imposed) {
  PolyFit f;
  f.t_ref = t_ref;
  f.g_imposed = g_imposed;
  f.n = idx.size();
  double span = 0;
  for (std::size_t i : idx) span = std::max(span, std::abs(t[i] - t_ref));
  f.scale = span > 0 ? span : 1;
  const Eigen::Index p = degree + 1;
  Eigen::MatrixXd X(static_cast<Eigen::Index>(idx.size()), p);
  Eigen::VectorXd b(static_cast<Eigen::Index>(idx.size()));
  for (std::size_t r = 0; r < idx.size(); ++r) {
    const double dt = t[idx[r]] - t_ref;
    const double tau = dt / f.scale;
    double pw = 1;
    for (Eigen::Index k = 0; k < p; ++k, pw *= tau) X(static_cast<Eigen::Index>(r), k) = pw;
    // Gravity imposed: fit y + g dt^2 / 2, which is linear in time during free flight.
    b[static_cast<Eigen::Index>(r)] = v[idx[r]] + 0.5 * g_imposed * dt * dt;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  if (qr.rank() < p) throw std::invalid_argument("reconstruct: degenerate fit (repeated times)");
  f.coef = qr.solve(b);
  f.rss = (X * f.coef - b).squaredNorm();
  f.cov_unit = (X.transpose() * X).inverse();
  return f;
}

/// The three free-flight fits of one side of the contact window.
struct SideFit {
  PolyFit x, y, theta;
  bool has_theta = false;
  std::size_t dof_pos() const { return (x.n - x.params()) + (y.n - y.params()); }
  std::size_t dof_theta() const { return has_theta ? theta.n - theta.params() : 0; }
};

SideFit fit_side(const Track& tr, const std::vector<std::size_t>& idx, double t_eval,
                 const std::optional<double>& gravity) {
  SideFit s;
  s.x = fit_poly(tr.t, tr.x, idx, 1, t_eval, 0);
  s.y = gravity ? fit_poly(tr.t, tr.y, idx, 1, t_eval, *gravity)
                : fit_poly(tr.t, tr.y, idx, 2, t_eval, 0);
  s.has_theta = !tr.theta.empty();
  if (s.has_theta) s.theta = fit_poly(tr.t, tr.theta, idx, 1, t_eval, 0);
  return s;
}

// ---------------------------------------------------------------------------------------------
// Noise scale and automatic window detection

using stats::median;

/// Deviations of each interior point from the straight line through its two neighbours, divided
/// by their standard deviation for unit white noise (sqrt(1 + w1^2 + w2^2)), then centred on
/// their median. In free flight they are pure noise (x, theta, y + g t^2/2 are linear in t; a
/// free-gravity y has a constant curvature offset the median removes); the contact frames are a
/// minority and do not move a median.
std::vector<double> interpolation_residuals(const std::vector<double>& t,
                                            const std::vector<double>& v) {
  std::vector<double> r;
  for (std::size_t i = 1; i + 1 < t.size(); ++i) {
    const double w1 = (t[i + 1] - t[i]) / (t[i + 1] - t[i - 1]);
    const double w2 = 1 - w1;
    r.push_back((v[i] - (w1 * v[i - 1] + w2 * v[i + 1])) / std::sqrt(1 + w1 * w1 + w2 * w2));
  }
  const double m = median(r);
  for (double& e : r) e -= m;
  return r;
}

/// Robust noise scale: 1.4826 x median absolute deviation (consistent for Gaussian noise).
double mad_scale(const std::vector<double>& r) {
  std::vector<double> a(r.size());
  std::transform(r.begin(), r.end(), a.begin(), [](double e) { return std::abs(e); });
  return 1.4826 * median(a);
}

struct NoiseScale {
  double position_m = 0, theta_rad = 0;
};

NoiseScale detection_noise(const Track& tr, const std::optional<double>& gravity) {
  NoiseScale s;
  if (tr.sigma_position_m > 0) {
    s.position_m = tr.sigma_position_m;
  } else {
    std::vector<double> yy = tr.y;
    if (gravity)
      for (std::size_t i = 0; i < yy.size(); ++i) yy[i] += 0.5 * *gravity * tr.t[i] * tr.t[i];
    std::vector<double> r = interpolation_residuals(tr.t, tr.x);
    const std::vector<double> ry = interpolation_residuals(tr.t, yy);
    r.insert(r.end(), ry.begin(), ry.end());
    double extent = 1;
    for (const auto* v : {&tr.x, &tr.y}) {
      const auto [lo, hi] = std::minmax_element(v->begin(), v->end());
      extent = std::max(extent, *hi - *lo);
    }
    // Floors: quantisation of the positions (pixels), and round-off for noise-free series
    // (LIGGGHTS output) where the MAD can be exactly zero.
    s.position_m = std::max({mad_scale(r), tr.resolution_m / std::sqrt(12.0), 1e-9 * extent});
  }
  if (!tr.theta.empty()) {
    if (tr.sigma_theta_rad > 0) {
      s.theta_rad = tr.sigma_theta_rad;
    } else {
      const auto [lo, hi] = std::minmax_element(tr.theta.begin(), tr.theta.end());
      double floor = 1e-9 * std::max(1.0, *hi - *lo);
      if (tr.mark_radius_m > 0 && tr.resolution_m > 0)
        floor =
            std::max(floor, std::sqrt(2.0) * tr.resolution_m / std::sqrt(12.0) / tr.mark_radius_m);
      s.theta_rad = std::max(mad_scale(interpolation_residuals(tr.t, tr.theta)), floor);
    }
  }
  return s;
}

/// Incremental least squares on a fixed basis (1, tau, tau^2 with tau = (t - t0) / T) so that a
/// window can grow point by point at O(1) cost per point (LIGGGHTS series have thousands).
class GrowingFit {
 public:
  GrowingFit(int degree, double t0, double scale, double g)
      : p_(degree + 1),
        t0_(t0),
        scale_(scale),
        g_(g),
        ata_(Eigen::MatrixXd::Zero(p_, p_)),
        atb_(Eigen::VectorXd::Zero(p_)) {}
  void add(double t, double v) {
    const Eigen::VectorXd phi = basis(t);
    ata_ += phi * phi.transpose();
    atb_ += phi * target(t, v);
  }
  /// Prediction residual at (t, v) divided by its standard deviation sigma * sqrt(1 + h).
  double z(double t, double v, double sigma) const {
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(ata_);
    const Eigen::VectorXd c = ldlt.solve(atb_);
    const Eigen::VectorXd phi = basis(t);
    const double h = phi.dot(ldlt.solve(phi));
    return (target(t, v) - phi.dot(c)) / (sigma * std::sqrt(1 + std::max(0.0, h)));
  }

 private:
  Eigen::VectorXd basis(double t) const {
    Eigen::VectorXd phi(p_);
    const double tau = (t - t0_) / scale_;
    double pw = 1;
    for (Eigen::Index k = 0; k < p_; ++k, pw *= tau) phi[k] = pw;
    return phi;
  }
  double target(double t, double v) const {
    const double dt = t - t0_;
    return v + 0.5 * g_ * dt * dt;
  }
  Eigen::Index p_;
  double t0_, scale_, g_;
  Eigen::MatrixXd ata_;
  Eigen::VectorXd atb_;
};

/// Cost of the free-flight window at one end of the track (forward from the first point or
/// backward from the last), for every possible extent. Walking away from the end, each point j
/// is predicted by the free-flight fit of the points before it; z_j^2 is its squared prediction
/// residual divided by its variance sigma^2 (1 + leverage), summed over x, y and theta. Adding
/// point j raises the weighted residual sum of squares of the fit by exactly z_j^2 (recursive
/// least squares), so C(j) = sum_{i <= j} (z_i^2 - k^2) is "misfit minus k^2 per point
/// explained". Returned per track index (the window's last point for forward, its first point
/// for backward); +inf for extents shorter than the seed. `z2` receives z_j^2 per track index.
std::vector<double> window_costs(const Track& tr, bool forward, std::size_t seed, double k,
                                 const NoiseScale& noise, const std::optional<double>& gravity,
                                 std::vector<double>& z2) {
  const std::size_t n = tr.t.size();
  auto at = [&](std::size_t j) { return forward ? j : n - 1 - j; };
  const double t0 = tr.t[at(0)];
  const double scale = std::max(std::abs(tr.t.back() - tr.t.front()), 1e-300);
  GrowingFit fx(1, t0, scale, 0), fy(gravity ? 1 : 2, t0, scale, gravity.value_or(0.0)),
      fth(1, t0, scale, 0);
  const bool has_theta = !tr.theta.empty();
  auto add = [&](std::size_t i) {
    fx.add(tr.t[i], tr.x[i]);
    fy.add(tr.t[i], tr.y[i]);
    if (has_theta) fth.add(tr.t[i], tr.theta[i]);
  };
  std::vector<double> cost(n, std::numeric_limits<double>::infinity());
  z2.assign(n, 0.0);
  for (std::size_t j = 0; j < seed; ++j) add(at(j));
  double c = 0;
  cost[at(seed - 1)] = 0;
  for (std::size_t j = seed; j < n; ++j) {
    const std::size_t i = at(j);
    const double zx = fx.z(tr.t[i], tr.x[i], noise.position_m);
    const double zy = fy.z(tr.t[i], tr.y[i], noise.position_m);
    const double zt = has_theta ? fth.z(tr.t[i], tr.theta[i], noise.theta_rad) : 0.0;
    z2[i] = zx * zx + zy * zy + zt * zt;
    c += z2[i] - k * k;
    cost[i] = c;
    add(i);
  }
  return cost;
}

/// The pair (b, a), b < a, minimising C_lead(b) + C_trail(a): the last point of the incoming
/// free flight and the first of the outgoing one. Being a global minimum, it is neither stopped
/// by an isolated mis-pointed frame (later good points pay for it) nor dragged into the contact
/// by one lucky point, and the two windows never overlap.
std::pair<std::size_t, std::size_t> best_windows(const std::vector<double>& lead,
                                                 const std::vector<double>& trail) {
  const std::size_t n = lead.size();
  double best = std::numeric_limits<double>::infinity();
  std::pair<std::size_t, std::size_t> arg{n, n};
  double prefix_min = std::numeric_limits<double>::infinity();
  std::size_t prefix_arg = n;
  for (std::size_t a = 1; a < n; ++a) {
    if (lead[a - 1] < prefix_min) {
      prefix_min = lead[a - 1];
      prefix_arg = a - 1;
    }
    if (prefix_arg < n && std::isfinite(trail[a]) && prefix_min + trail[a] < best) {
      best = prefix_min + trail[a];
      arg = {prefix_arg, a};
    }
  }
  return arg;
}

/// Time where the fitted free flight crosses `level`, on its falling branch (incoming flight) or
/// its rising branch (outgoing flight). The fit is a quadratic in d = t - t_ref, so the crossing
/// is solved exactly: it comes from all the free-flight points, not from the one noisy frame
/// nearest to the level. When the fitted parabola never reaches the level (its apex is below),
/// the nearer end of [ta, tb] (the last free frame and the first contact frame) is returned.
double crossing_time(const PolyFit& fit, double level, bool falling, double ta, double tb) {
  const double s = fit.scale;
  const double c2 = fit.coef.size() > 2 ? fit.coef[2] / (s * s) : 0.0;
  const double qa = c2 - 0.5 * fit.g_imposed, qb = fit.coef[1] / s, qc = fit.coef[0] - level;
  std::vector<double> roots;
  if (qa == 0) {
    if (qb != 0) roots.push_back(-qc / qb);
  } else {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      // Numerically stable pair of roots.
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      if (q != 0) roots.push_back(qc / q);
      roots.push_back(q / qa);
    }
  }
  for (double d : roots) {
    const double slope = 2 * qa * d + qb;
    if (falling ? slope < 0 : slope > 0) return fit.t_ref + d;
  }
  const double fa = std::abs(fit.value(ta) - level), fb = std::abs(fit.value(tb) - level);
  return fa <= fb ? ta : tb;
}

void check_track(const Track& tr) {
  const std::size_t n = tr.t.size();
  if (tr.x.size() != n || tr.y.size() != n || (!tr.theta.empty() && tr.theta.size() != n))
    throw std::invalid_argument("reconstruct: track columns t, x, y, theta differ in length");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(tr.t[i]) || !std::isfinite(tr.x[i]) || !std::isfinite(tr.y[i]) ||
        (!tr.theta.empty() && !std::isfinite(tr.theta[i])))
      throw std::invalid_argument("reconstruct: non-finite value at point " + std::to_string(i));
    if (i > 0 && !(tr.t[i] > tr.t[i - 1]))
      throw std::invalid_argument("reconstruct: time must increase strictly (point " +
                                  std::to_string(i) + ")");
  }
}

// The free-flight points on each side of the contact window.
struct Sides {
  std::vector<std::size_t> before, after;
};

void check_options(const ReconstructOptions& options) {
  const auto& g = options.gravity_mps2;
  if (g && !std::isfinite(*g)) throw std::invalid_argument("reconstruct: gravity must be finite");
  if (options.contact_start_s.has_value() != options.contact_end_s.has_value())
    throw std::invalid_argument("reconstruct: give both ends of the contact window, or neither");
  if (options.ground_y_m.has_value() != options.contact_radius_m.has_value())
    throw std::invalid_argument(
        "reconstruct: the ground-level criterion needs both the ground level and the contact "
        "radius");
}

// The window the caller gives.
Sides given_window(const Track& track, const ReconstructOptions& options, Reconstruction& rec) {
  Sides s;
  rec.window_method = "given";
  rec.contact_start_s = *options.contact_start_s;
  rec.contact_end_s = *options.contact_end_s;
  if (!(rec.contact_start_s < rec.contact_end_s))
    throw std::invalid_argument("reconstruct: the contact window must have start < end");
  for (std::size_t i = 0; i < track.t.size(); ++i) {
    if (track.t[i] <= rec.contact_start_s) s.before.push_back(i);
    if (track.t[i] >= rec.contact_end_s) s.after.push_back(i);
  }
  return s;
}

// Paper Fig. 8b: contact while the centre is within one radius of the ground surface; the ends
// are where the free-flight fits cross that level.
Sides ground_level_window(const Track& track, const ReconstructOptions& options,
                          Reconstruction& rec) {
  const std::size_t n = track.t.size();
  const auto& g = options.gravity_mps2;
  Sides s;
  rec.window_method = "ground-level";
  rec.window_detected = true;
  const double level = *options.ground_y_m + *options.contact_radius_m;
  std::size_t c0 = n, c1 = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (track.y[i] <= level) {
      c0 = std::min(c0, i);
      c1 = i;
    }
  if (c0 == n)
    throw std::invalid_argument(
        "reconstruct: the block centre never comes within the contact "
        "radius of the ground level");
  for (std::size_t i = 0; i < c0; ++i) s.before.push_back(i);
  for (std::size_t i = c1 + 1; i < n; ++i) s.after.push_back(i);
  if (s.before.size() < 3 || s.after.size() < 3)
    throw std::invalid_argument(
        "reconstruct: fewer than 3 free-flight points on one side of "
        "the ground contact");
  const SideFit fb = fit_side(track, s.before, track.t[s.before.back()], g);
  const SideFit fa = fit_side(track, s.after, track.t[s.after.front()], g);
  rec.contact_start_s = crossing_time(fb.y, level, true, track.t[c0 - 1], track.t[c0]);
  rec.contact_end_s = crossing_time(fa.y, level, false, track.t[c1], track.t[c1 + 1]);
  if (!(rec.contact_start_s < rec.contact_end_s))
    throw std::invalid_argument(
        "reconstruct: the free-flight fits cross the contact level in "
        "the wrong order (check --ground and --radius)");
  return s;
}

// The automatic window: the longest leading and trailing runs consistent with ballistic flight
// within the noise (window_costs, best_windows), less the guard points.
Sides ballistic_window(const Track& track, const ReconstructOptions& options, Reconstruction& rec) {
  const std::size_t n = track.t.size();
  const auto& g = options.gravity_mps2;
  Sides s;
  rec.window_method = "ballistic-residuals";
  rec.window_detected = true;
  const std::size_t seed =
      options.detection_seed_points ? options.detection_seed_points : (g ? 5 : 6);
  if (seed < (g ? 3u : 4u))
    throw std::invalid_argument("reconstruct: the detection needs at least " +
                                std::to_string(g ? 3 : 4) + " seed points");
  if (n < 2 * seed + 1)
    throw std::invalid_argument("reconstruct: a track of " + std::to_string(n) +
                                " points is too short for the automatic window detection (" +
                                std::to_string(seed) + " seed points on each side)");
  const NoiseScale noise = detection_noise(track, g);
  std::vector<double> z2_lead, z2_trail;
  const std::vector<double> lead =
      window_costs(track, true, seed, options.detection_k_sigma, noise, g, z2_lead);
  const std::vector<double> trail =
      window_costs(track, false, seed, options.detection_k_sigma, noise, g, z2_trail);
  const auto [b, a] = best_windows(lead, trail);
  if (b >= n)
    throw std::invalid_argument("reconstruct: the track is too short to detect a contact window");
  const double k2 = options.detection_k_sigma * options.detection_k_sigma;
  for (std::size_t i = 0; i <= b; ++i) {
    s.before.push_back(i);
    if (z2_lead[i] > k2) ++rec.flagged_points;
  }
  for (std::size_t i = a; i < n; ++i) {
    s.after.push_back(i);
    if (z2_trail[i] > k2) ++rec.flagged_points;
  }
  // Without any contact the incoming window alone would extend to the last point.
  if (std::min_element(lead.begin(), lead.end()) == lead.end() - 1)
    throw std::invalid_argument(
        "reconstruct: no contact detected: the whole track is one ballistic flight within the "
        "noise (give the window with --window)");
  for (std::size_t k = 0; k < options.detection_guard_points && s.before.size() > 3; ++k)
    s.before.pop_back();
  for (std::size_t k = 0; k < options.detection_guard_points && s.after.size() > 3; ++k)
    s.after.erase(s.after.begin());
  rec.contact_start_s = track.t[s.before.back()];
  rec.contact_end_s = track.t[s.after.front()];
  return s;
}

// Noise levels: given, or pooled residual variances of both sides (x and y share the pointing
// noise; theta has its own).
void noise_levels(const Track& track, const SideFit& fb, const SideFit& fa, Reconstruction& rec) {
  const std::size_t dof_pos = fb.dof_pos() + fa.dof_pos();
  const std::size_t dof_th = fb.dof_theta() + fa.dof_theta();
  const double rss_pos = fb.x.rss + fb.y.rss + fa.x.rss + fa.y.rss;
  const double rss_th = fb.has_theta ? fb.theta.rss + fa.theta.rss : 0;
  if (track.sigma_position_m > 0) {
    rec.sigma_source = "given";
    rec.sigma_position_m = track.sigma_position_m;
  } else {
    rec.sigma_source = "residuals";
    rec.sigma_position_m = dof_pos > 0 ? std::sqrt(rss_pos / static_cast<double>(dof_pos)) : kNaN;
  }
  if (track.sigma_theta_rad > 0)
    rec.sigma_theta_rad = track.sigma_theta_rad;
  else if (track.sigma_position_m > 0 && track.mark_radius_m > 0)
    rec.sigma_theta_rad = std::sqrt(2.0) * track.sigma_position_m / track.mark_radius_m;
  else
    rec.sigma_theta_rad = dof_th > 0 ? std::sqrt(rss_th / static_cast<double>(dof_th)) : kNaN;
}

// Position, velocity and its standard error of one side's fit at the window's end te.
void side_state(const SideFit& f, double te, const Reconstruction& rec, Vel3& v, Vel3& sv,
                Vel3& pos) {
  pos[0] = f.x.value(te);
  pos[1] = f.y.value(te);
  pos[2] = f.has_theta ? f.theta.value(te) : kNaN;
  v[kVx] = f.x.derivative(te);
  v[kVy] = f.y.derivative(te);
  sv[kVx] = rec.sigma_position_m * f.x.derivative_sd_unit(te);
  sv[kVy] = rec.sigma_position_m * f.y.derivative_sd_unit(te);
  v[kW] = f.has_theta ? f.theta.derivative(te) : kNaN;
  sv[kW] = f.has_theta ? rec.sigma_theta_rad * f.theta.derivative_sd_unit(te) : kNaN;
}

// Gravity of one side: imposed, or fitted from y = ... + c2 tau^2 with tau = dt / scale, so
// g = -2 c2 / scale^2.
void side_gravity(const SideFit& f, const std::optional<double>& g, double sigma_position_m,
                  double& gv, double& sg) {
  if (g) {
    gv = *g;
    sg = 0;
  } else {
    const double s2 = f.y.scale * f.y.scale;
    gv = -2 * f.y.coef[2] / s2;
    sg = 2 * sigma_position_m * std::sqrt(f.y.cov_unit(2, 2)) / s2;
  }
}

}  // namespace

Reconstruction reconstruct(const Track& track, const ReconstructOptions& options) {
  check_track(track);
  check_options(options);
  Reconstruction rec;
  const Sides s = options.contact_start_s ? given_window(track, options, rec)
                  : options.ground_y_m    ? ground_level_window(track, options, rec)
                                          : ballistic_window(track, options, rec);
  if (s.before.size() < 3 || s.after.size() < 3)
    throw std::invalid_argument(
        "reconstruct: fewer than 3 points on one side of the contact window (" +
        std::to_string(s.before.size()) + " before, " + std::to_string(s.after.size()) + " after)");
  rec.points_before = s.before.size();
  rec.points_after = s.after.size();

  const auto& g = options.gravity_mps2;
  const SideFit fb = fit_side(track, s.before, rec.contact_start_s, g);
  const SideFit fa = fit_side(track, s.after, rec.contact_end_s, g);
  noise_levels(track, fb, fa, rec);
  side_state(fb, rec.contact_start_s, rec, rec.vin, rec.sigma_vin, rec.position_in);
  side_state(fa, rec.contact_end_s, rec, rec.vout, rec.sigma_vout, rec.position_out);
  side_gravity(fb, g, rec.sigma_position_m, rec.gravity_before_mps2, rec.sigma_gravity_before_mps2);
  side_gravity(fa, g, rec.sigma_position_m, rec.gravity_after_mps2, rec.sigma_gravity_after_mps2);
  rec.rms_residual_before_m =
      std::sqrt((fb.x.rss + fb.y.rss) / (2.0 * static_cast<double>(s.before.size())));
  rec.rms_residual_after_m =
      std::sqrt((fa.x.rss + fa.y.rss) / (2.0 * static_cast<double>(s.after.size())));
  return rec;
}

Impact to_impact(const Reconstruction& r, std::string id, std::string shape) {
  Impact i;
  i.id = std::move(id);
  i.shape = std::move(shape);
  i.vin = r.vin;
  i.vout = r.vout;
  i.sigma_vin = r.sigma_vin;
  i.sigma_vout = r.sigma_vout;
  i.contact_duration = r.contact_end_s - r.contact_start_s;
  return i;
}

}  // namespace ricochet::kinematics
