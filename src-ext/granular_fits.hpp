// Fits of the granular-impact laws a sphere dropped into a bed must follow (issue 11, item 4;
// docs/granular-impact-checks.md). Pure functions on plain arrays: no LIGGGHTS, no I/O, so they
// are unit-tested on analytic trajectories (tests/dem/granular_fits_test.cpp).
//
//  - Uehara, Ambroso, Ojha & Durian 2003, PRL 90, 194301, Eq. (1): the final depth of a sphere
//    (diameter D_b, density rho_b) dropped into a granular bed (bulk density rho_g, angle of
//    repose theta_r, mu = tan theta_r) from a total drop distance H = h + d is
//      d = (0.14 / mu) (rho_b / rho_g)^(1/2) D_b^(2/3) H^(1/3).
//  - Katsuragi & Durian 2007, Nature Physics 3, 420, Eq. (1): the stopping force of the bed on
//    the projectile, depth z positive down from the surface,
//      m z'' = m g - (m / d1) z'^2 - k z.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace ricochet::dem {

/// Ordinary least squares y ~ sum_j beta_j columns[j], with standard errors.
struct LinearFit {
  std::vector<double> beta;  ///< coefficients, one per column
  std::vector<double> se;    ///< their standard errors (residual variance x inflation)
  double residual_sd = 0;    ///< sqrt(RSS / (n - p))
  std::size_t n = 0;
};

/// Solves the normal equations (columns scaled to unit norm first). `variance_inflation` >= 1
/// multiplies the coefficient variances: residuals correlated over w consecutive samples carry
/// about n / w independent pieces of information, hence inflation w. Throws std::invalid_argument
/// when there are fewer samples than columns + 1 or the columns are collinear.
LinearFit least_squares(const std::vector<std::vector<double>>& columns, std::span<const double> y,
                        double variance_inflation = 1.0);

/// y = A x^n fitted by least squares of ln y on ln x.
struct PowerLawFit {
  double exponent = 0, exponent_se = 0;
  double prefactor = 0;         ///< A = exp(intercept)
  double log_prefactor_se = 0;  ///< standard error of ln A
  double residual_sd_log = 0;   ///< in ln y
  std::size_t n = 0;
};
/// Needs at least 3 points with x, y > 0 and two distinct x (std::invalid_argument otherwise).
PowerLawFit fit_power_law(std::span<const double> x, std::span<const double> y);

/// Uehara et al. 2003 Eq. (1): d = (0.14 / mu) (rho_b / rho_g)^(1/2) D_b^(2/3) H^(1/3) [m].
double uehara_depth_m(double H_m, double rho_ball_kgm3, double rho_bulk_kgm3, double D_ball_m,
                      double mu);

/// The penetration depths d of drops from total drop distances H against Uehara's law.
struct UeharaCheck {
  PowerLawFit fit;                ///< d = A H^n
  double scale = 0;               ///< (rho_b / rho_g)^(1/2) D_b^(2/3) [m^(2/3)]
  double c_fitted = 0;            ///< C in d = C scale H^(1/3) (exponent fixed): exp(mean ln ratio)
  double c_fitted_se = 0;         ///< its standard error (delta method on the mean of ln)
  double c_expected = 0;          ///< Uehara's 0.14 / mu
  double exponent_deviation = 0;  ///< n - 1/3
  double tolerance = 0.05;
  bool exponent_pass = false;  ///< |n - 1/3| <= tolerance
};
UeharaCheck check_uehara(std::span<const double> H_m, std::span<const double> d_m,
                         double rho_ball_kgm3, double rho_bulk_kgm3, double D_ball_m, double mu,
                         double tolerance = 0.05);

/// First and second time derivatives of z(t) by a local quadratic least-squares fit over the
/// 2 half_window + 1 nearest samples (Savitzky & Golay 1964, on the actual sample times, so the
/// spacing may vary); one-sided windows at the ends. Needs t strictly increasing and
/// z.size() == t.size() >= 3.
struct Derivatives {
  std::vector<double> v, a;
};
Derivatives local_quadratic_derivatives(std::span<const double> t, std::span<const double> z,
                                        std::size_t half_window);

/// One point of a penetration: depth z (positive down) [m], z' [m/s], z'' [m/s^2].
struct KdSample {
  double z_m = 0, v_mps = 0, a_mps2 = 0;
  std::size_t index = 0;  ///< record the sample comes from (penetration_samples)
};

/// The samples of one drop's penetration phase from its depth record z(t) (positive down, 0 at
/// the levelled surface): derivatives by local_quadratic_derivatives(half_window) over the whole
/// record, then the samples from the first one whose derivative window lies entirely at z >= 0
/// (half_window records after the first at z >= 0: a window straddling the surface mixes free
/// fall and drag) up to (excluding) the first one whose speed z' is below stop_fraction x the
/// speed there (Katsuragi and Durian's law ends in an abrupt stop that it does not describe).
/// `z_start_m`: the phase starts at the first record at z >= z_start_m instead of 0 (e.g. the
/// depth at the first contact, above the mean surface for coarse grains; an offset of z only
/// shifts the fitted constant term, g + (k / m) z_start).
std::vector<KdSample> penetration_samples(std::span<const double> t, std::span<const double> z,
                                          std::size_t half_window, double stop_fraction = 0.1,
                                          double z_start_m = 0.0);

/// Katsuragi & Durian 2007 Eq. (1) fitted as the linear model z'' = c0 - z'^2 / d1 - (k / m) z.
struct KatsuragiDurianFit {
  double g_mps2 = 0, g_se = 0;  ///< c0 (the law says g) or the imposed g
  bool g_fixed = false;
  double inv_d1_per_m = 0, inv_d1_se = 0;
  double k_over_m_per_s2 = 0, k_over_m_se = 0;
  double d1_m = 0, d1_se = 0;  ///< 1 / inv_d1 (standard error by the delta method)
  double mass_kg = 0;
  double drag_kg_per_m = 0, drag_se = 0;  ///< m / d1: the catalog's inertial_drag cd
  double k_Npm = 0, k_se = 0;             ///< k = m (k / m)
  std::size_t n = 0;
  double variance_inflation = 1;
  double residual_sd = 0;  ///< of z'' [m/s^2]
};
/// Least squares over `samples` (several drops may be pooled: one d1 and one k for all, as the
/// law claims). `g_fixed_mps2`: impose c0 = g instead of fitting it. `variance_inflation`: see
/// least_squares (the derivative window correlates neighbouring samples).
KatsuragiDurianFit fit_katsuragi_durian(std::span<const KdSample> samples, double mass_kg,
                                        double variance_inflation = 1.0,
                                        std::optional<double> g_fixed_mps2 = std::nullopt);

/// Katsuragi & Durian's law with a viscous term, an exploratory extension (2026-12-07): a stop
/// whose duration does not depend on the impact speed (Pica Ciamarra et al. 2004, PRL 92, 194301)
/// is what a force linear in the speed gives (z = m v0 / b, time constant m / b), and the
/// force-residual discovery on the resolved block (docs/diagnosis.md) selects such a term:
///   m z'' = m c0 - b z' - (m / d1) z'^2 - k z,
/// fitted linearly in (c0, b / m, 1 / d1, k / m). The drag is reported as m / d1 [kg/m] (1 / d1
/// may be near 0 or negative once b takes the speed dependence).
struct ViscousDragFit {
  double g_mps2 = 0, g_se = 0;            ///< c0
  double b_Nspm = 0, b_se = 0;            ///< the viscous coefficient b [N s/m]
  double drag_kg_per_m = 0, drag_se = 0;  ///< m / d1
  double k_Npm = 0, k_se = 0;
  double mass_kg = 0;
  std::size_t n = 0;
  double residual_sd = 0;  ///< of z'' [m/s^2]
};
ViscousDragFit fit_viscous_katsuragi_durian(std::span<const KdSample> samples, double mass_kg,
                                            double variance_inflation = 1.0);

/// The slope of a heap's free surface h(x) fitted on the points whose height is between lo_frac
/// and hi_frac of the largest height (the flank, away from the crest and the thin runout); the
/// angle of repose is atan(|slope|).
struct SlopeFit {
  double slope = 0, slope_se = 0;
  double angle_deg = 0, angle_se_deg = 0;
  double x_lo_m = 0, x_hi_m = 0;  ///< extent of the fitted points
  std::size_t n = 0;
};
/// Non-finite heights are skipped. Throws std::invalid_argument with fewer than 3 points in
/// the band.
SlopeFit fit_repose_slope(std::span<const double> x_m, std::span<const double> h_m,
                          double lo_frac = 0.15, double hi_frac = 0.85);

}  // namespace ricochet::dem
