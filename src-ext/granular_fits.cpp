#include "granular_fits.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace ricochet::dem {

namespace {

// Inverse of a small symmetric positive definite matrix (Gauss-Jordan with partial pivoting);
// throws when it is singular to working precision.
std::vector<std::vector<double>> invert(std::vector<std::vector<double>> a) {
  const std::size_t p = a.size();
  std::vector<std::vector<double>> inv(p, std::vector<double>(p, 0.0));
  for (std::size_t i = 0; i < p; ++i) inv[i][i] = 1.0;
  for (std::size_t c = 0; c < p; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < p; ++r)
      if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
    if (std::abs(a[piv][c]) < 1e-12)
      throw std::invalid_argument("least squares: the columns are collinear");
    std::swap(a[c], a[piv]);
    std::swap(inv[c], inv[piv]);
    const double d = a[c][c];
    for (std::size_t k = 0; k < p; ++k) {
      a[c][k] /= d;
      inv[c][k] /= d;
    }
    for (std::size_t r = 0; r < p; ++r) {
      if (r == c) continue;
      const double f = a[r][c];
      for (std::size_t k = 0; k < p; ++k) {
        a[r][k] -= f * a[c][k];
        inv[r][k] -= f * inv[c][k];
      }
    }
  }
  return inv;
}

}  // namespace

LinearFit least_squares(const std::vector<std::vector<double>>& columns, std::span<const double> y,
                        double variance_inflation) {
  const std::size_t p = columns.size();
  const std::size_t n = y.size();
  if (p == 0) throw std::invalid_argument("least squares: no column");
  for (const auto& c : columns)
    if (c.size() != n) throw std::invalid_argument("least squares: column sizes differ");
  if (n < p + 1)
    throw std::invalid_argument("least squares: " + std::to_string(n) + " samples for " +
                                std::to_string(p) + " coefficients");
  // Unit-norm columns: the normal matrix is then well scaled whatever the units.
  std::vector<double> norm(p, 0.0);
  for (std::size_t j = 0; j < p; ++j) {
    for (double v : columns[j]) norm[j] += v * v;
    norm[j] = std::sqrt(norm[j]);
    if (!(norm[j] > 0)) throw std::invalid_argument("least squares: a column is zero");
  }
  std::vector<std::vector<double>> ata(p, std::vector<double>(p, 0.0));
  std::vector<double> aty(p, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < p; ++j) {
      const double xj = columns[j][i] / norm[j];
      aty[j] += xj * y[i];
      for (std::size_t k = 0; k <= j; ++k) ata[j][k] += xj * columns[k][i] / norm[k];
    }
  for (std::size_t j = 0; j < p; ++j)
    for (std::size_t k = j + 1; k < p; ++k) ata[j][k] = ata[k][j];
  const auto inv = invert(ata);
  LinearFit f;
  f.n = n;
  f.beta.assign(p, 0.0);
  for (std::size_t j = 0; j < p; ++j)
    for (std::size_t k = 0; k < p; ++k) f.beta[j] += inv[j][k] * aty[k];
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double fit = 0;
    for (std::size_t j = 0; j < p; ++j) fit += f.beta[j] * columns[j][i] / norm[j];
    rss += (y[i] - fit) * (y[i] - fit);
  }
  const double s2 = rss / static_cast<double>(n - p);
  f.residual_sd = std::sqrt(s2);
  f.se.assign(p, 0.0);
  for (std::size_t j = 0; j < p; ++j) {
    f.se[j] =
        std::sqrt(std::max(0.0, s2 * inv[j][j] * std::max(1.0, variance_inflation))) / norm[j];
    f.beta[j] /= norm[j];
  }
  return f;
}

PowerLawFit fit_power_law(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size()) throw std::invalid_argument("power law: x and y sizes differ");
  std::vector<double> one, lx, ly;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(x[i] > 0) || !(y[i] > 0))
      throw std::invalid_argument("power law: x and y must be positive");
    one.push_back(1.0);
    lx.push_back(std::log(x[i]));
    ly.push_back(std::log(y[i]));
  }
  if (lx.size() < 3) throw std::invalid_argument("power law: needs at least 3 points");
  if (*std::max_element(lx.begin(), lx.end()) == *std::min_element(lx.begin(), lx.end()))
    throw std::invalid_argument("power law: needs two distinct x");
  const LinearFit f = least_squares({one, lx}, ly);
  PowerLawFit p;
  p.n = f.n;
  p.exponent = f.beta[1];
  p.exponent_se = f.se[1];
  p.prefactor = std::exp(f.beta[0]);
  p.log_prefactor_se = f.se[0];
  p.residual_sd_log = f.residual_sd;
  return p;
}

double uehara_depth_m(double H_m, double rho_ball_kgm3, double rho_bulk_kgm3, double D_ball_m,
                      double mu) {
  // Uehara et al. 2003, PRL 90, 194301, Eq. (1).
  return 0.14 / mu * std::sqrt(rho_ball_kgm3 / rho_bulk_kgm3) * std::cbrt(D_ball_m * D_ball_m) *
         std::cbrt(H_m);
}

UeharaCheck check_uehara(std::span<const double> H_m, std::span<const double> d_m,
                         double rho_ball_kgm3, double rho_bulk_kgm3, double D_ball_m, double mu,
                         double tolerance) {
  UeharaCheck c;
  c.fit = fit_power_law(H_m, d_m);
  // Uehara et al. 2003 Eq. (1) with the prefactor C = 0.14 / mu left free:
  // d = C (rho_b / rho_g)^(1/2) D_b^(2/3) H^(1/3).
  c.scale = std::sqrt(rho_ball_kgm3 / rho_bulk_kgm3) * std::cbrt(D_ball_m * D_ball_m);
  c.c_expected = 0.14 / mu;
  double mean = 0, m2 = 0;
  const auto n = static_cast<double>(H_m.size());
  std::vector<double> lr;
  for (std::size_t i = 0; i < H_m.size(); ++i)
    lr.push_back(std::log(d_m[i] / (c.scale * std::cbrt(H_m[i]))));
  for (double v : lr) mean += v / n;
  for (double v : lr) m2 += (v - mean) * (v - mean);
  c.c_fitted = std::exp(mean);
  c.c_fitted_se = c.c_fitted * std::sqrt(m2 / (n - 1) / n);
  c.exponent_deviation = c.fit.exponent - 1.0 / 3.0;
  c.tolerance = tolerance;
  c.exponent_pass = std::abs(c.exponent_deviation) <= tolerance;
  return c;
}

Derivatives local_quadratic_derivatives(std::span<const double> t, std::span<const double> z,
                                        std::size_t half_window) {
  const std::size_t n = t.size();
  if (z.size() != n || n < 3) throw std::invalid_argument("derivatives: needs >= 3 samples");
  for (std::size_t i = 1; i < n; ++i)
    if (!(t[i] > t[i - 1])) throw std::invalid_argument("derivatives: t must increase");
  const std::size_t w = std::min(std::max<std::size_t>(half_window, 1), (n - 1) / 2);
  Derivatives d;
  d.v.resize(n);
  d.a.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    // Window of 2w + 1 samples centred on i, shifted inside the record at the ends.
    const std::size_t lo = i < w ? 0 : std::min(i - w, n - 1 - 2 * w);
    const std::size_t hi = lo + 2 * w;
    // z ~ c0 + c1 s + c2 s^2, s = t - t_i (Savitzky & Golay 1964 on the actual times):
    // z'(t_i) = c1, z''(t_i) = 2 c2.
    double s[5] = {0, 0, 0, 0, 0}, r[3] = {0, 0, 0};
    for (std::size_t j = lo; j <= hi; ++j) {
      const double u = t[j] - t[i];
      double p = 1;
      for (int k = 0; k < 5; ++k) {
        s[k] += p;
        if (k < 3) r[k] += p * z[j];
        p *= u;
      }
    }
    const std::vector<std::vector<double>> m = {
        {s[0], s[1], s[2]}, {s[1], s[2], s[3]}, {s[2], s[3], s[4]}};
    // The window's time scale makes m badly scaled: solve in units of the window half-width.
    const double tau = std::max(std::abs(t[lo] - t[i]), std::abs(t[hi] - t[i]));
    std::vector<std::vector<double>> ms(3, std::vector<double>(3));
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) ms[a][b] = m[a][b] / std::pow(tau, a + b);
    const auto inv = invert(ms);
    double c[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) c[a] += inv[a][b] * r[b] / std::pow(tau, b);
    d.v[i] = c[1] / tau;
    d.a[i] = 2 * c[2] / (tau * tau);
  }
  return d;
}

std::vector<KdSample> penetration_samples(std::span<const double> t, std::span<const double> z,
                                          std::size_t half_window, double stop_fraction,
                                          double z_start_m) {
  const Derivatives d = local_quadratic_derivatives(t, z, half_window);
  std::vector<KdSample> out;
  std::size_t i0 = t.size();
  for (std::size_t i = 0; i < t.size(); ++i)
    if (z[i] >= z_start_m) {
      i0 = i;
      break;
    }
  // The first sample whose window [i - w, i + w] is in the sand.
  i0 += half_window;
  if (i0 >= t.size()) return out;
  const double v0 = d.v[i0];
  if (!(v0 > 0)) return out;
  for (std::size_t i = i0; i < t.size(); ++i) {
    if (d.v[i] < stop_fraction * v0) break;
    out.push_back({z[i], d.v[i], d.a[i], i});
  }
  return out;
}

namespace {

// The regression columns of the Katsuragi-Durian family, one place for both fits so that their
// signs cannot drift apart: each term as it enters z'' (z down, v = z' > 0 while penetrating), and
// the acceleration less a fixed part (g when g is not fitted).
struct KdColumns {
  std::vector<double> one, v, v2, z, a;
};

KdColumns kd_columns(std::span<const KdSample> samples, double a_fixed_mps2) {
  KdColumns c;
  for (const auto& s : samples) {
    c.one.push_back(1.0);
    c.v.push_back(-s.v_mps);
    c.v2.push_back(-s.v_mps * s.v_mps);
    c.z.push_back(-s.z_m);
    c.a.push_back(s.a_mps2 - a_fixed_mps2);
  }
  return c;
}

}  // namespace

ViscousDragFit fit_viscous_katsuragi_durian(std::span<const KdSample> samples, double mass_kg,
                                            double variance_inflation) {
  // z'' = c0 - (b / m) z' - z'^2 / d1 - (k / m) z: linear in (c0, b / m, 1 / d1, k / m).
  const KdColumns c = kd_columns(samples, 0.0);
  const LinearFit lf = least_squares({c.one, c.v, c.v2, c.z}, c.a, variance_inflation);
  ViscousDragFit f;
  f.mass_kg = mass_kg;
  f.n = samples.size();
  f.g_mps2 = lf.beta[0];
  f.g_se = lf.se[0];
  f.b_Nspm = mass_kg * lf.beta[1];
  f.b_se = mass_kg * lf.se[1];
  f.drag_kg_per_m = mass_kg * lf.beta[2];
  f.drag_se = mass_kg * lf.se[2];
  f.k_Npm = mass_kg * lf.beta[3];
  f.k_se = mass_kg * lf.se[3];
  f.residual_sd = lf.residual_sd;
  return f;
}

KatsuragiDurianFit fit_katsuragi_durian(std::span<const KdSample> samples, double mass_kg,
                                        double variance_inflation,
                                        std::optional<double> g_fixed_mps2) {
  // Katsuragi & Durian 2007 Eq. (1) divided by m: z'' = g - z'^2 / d1 - (k / m) z, linear in
  // (g, 1 / d1, k / m).
  const KdColumns c = kd_columns(samples, g_fixed_mps2.value_or(0.0));
  KatsuragiDurianFit f;
  f.mass_kg = mass_kg;
  f.variance_inflation = std::max(1.0, variance_inflation);
  f.n = samples.size();
  LinearFit lf;
  if (g_fixed_mps2) {
    lf = least_squares({c.v2, c.z}, c.a, variance_inflation);
    f.g_fixed = true;
    f.g_mps2 = *g_fixed_mps2;
    f.inv_d1_per_m = lf.beta[0];
    f.inv_d1_se = lf.se[0];
    f.k_over_m_per_s2 = lf.beta[1];
    f.k_over_m_se = lf.se[1];
  } else {
    lf = least_squares({c.one, c.v2, c.z}, c.a, variance_inflation);
    f.g_mps2 = lf.beta[0];
    f.g_se = lf.se[0];
    f.inv_d1_per_m = lf.beta[1];
    f.inv_d1_se = lf.se[1];
    f.k_over_m_per_s2 = lf.beta[2];
    f.k_over_m_se = lf.se[2];
  }
  f.residual_sd = lf.residual_sd;
  f.d1_m = 1.0 / f.inv_d1_per_m;
  f.d1_se = f.inv_d1_se / (f.inv_d1_per_m * f.inv_d1_per_m);
  f.drag_kg_per_m = mass_kg * f.inv_d1_per_m;
  f.drag_se = mass_kg * f.inv_d1_se;
  f.k_Npm = mass_kg * f.k_over_m_per_s2;
  f.k_se = mass_kg * f.k_over_m_se;
  return f;
}

SlopeFit fit_repose_slope(std::span<const double> x_m, std::span<const double> h_m, double lo_frac,
                          double hi_frac) {
  if (x_m.size() != h_m.size()) throw std::invalid_argument("repose slope: sizes differ");
  double h_max = -1e300;
  for (double h : h_m)
    if (std::isfinite(h)) h_max = std::max(h_max, h);
  std::vector<double> one, xs, hs;
  for (std::size_t i = 0; i < x_m.size(); ++i)
    if (std::isfinite(h_m[i]) && h_m[i] >= lo_frac * h_max && h_m[i] <= hi_frac * h_max) {
      one.push_back(1.0);
      xs.push_back(x_m[i]);
      hs.push_back(h_m[i]);
    }
  if (xs.size() < 3)
    throw std::invalid_argument("repose slope: fewer than 3 profile points on the flank");
  const LinearFit f = least_squares({one, xs}, hs);
  SlopeFit s;
  s.n = xs.size();
  s.slope = f.beta[1];
  s.slope_se = f.se[1];
  s.angle_deg = std::atan(std::abs(s.slope)) * 180.0 / std::numbers::pi;
  // d atan(s) / ds = 1 / (1 + s^2).
  s.angle_se_deg = s.slope_se / (1 + s.slope * s.slope) * 180.0 / std::numbers::pi;
  s.x_lo_m = *std::min_element(xs.begin(), xs.end());
  s.x_hi_m = *std::max_element(xs.begin(), xs.end());
  return s;
}

}  // namespace ricochet::dem
