#include "fit/error.hpp"

#include <algorithm>
#include <cmath>

namespace ricochet::fit {

Vel3 error_scale(const Vel3& measured, const ErrorOptions& options) {
  Vel3 d{};
  for (int k = 0; k < 3; ++k) d[k] = std::max(std::fabs(measured[k]), options.floor[k]);
  return d;
}

Vel3 release_error_terms(const Vel3& simulated, const Vel3& measured, const ErrorOptions& options) {
  const Vel3 d = error_scale(measured, options);
  Vel3 t{};
  for (int k = 0; k < 3; ++k) {
    const double r = (simulated[k] - measured[k]) / d[k];  // paper Eq. 7, one term
    t[k] = r * r;
  }
  return t;
}

double release_error(const Vel3& simulated, const Vel3& measured, const ErrorOptions& options) {
  const Vel3 t = release_error_terms(simulated, measured, options);
  return t[0] + t[1] + t[2];
}

std::array<double, 2> contact_error_scale(const Impact& impact, const ErrorOptions& options) {
  std::array<double, 2> d{1.0, 1.0};
  if (impact.penetration)
    d[0] = options.penetration_scale_m > 0
               ? options.penetration_scale_m
               : std::max(*impact.penetration, options.penetration_floor_m);
  if (impact.contact_duration)
    d[1] = options.contact_duration_scale_s > 0
               ? options.contact_duration_scale_s
               : std::max(*impact.contact_duration, options.contact_duration_floor_s);
  return d;
}

std::array<double, 2> contact_error_terms(double penetration_sim_m, double contact_duration_sim_s,
                                          const Impact& impact, const ErrorOptions& options) {
  const std::array<double, 2> d = contact_error_scale(impact, options);
  std::array<double, 2> t{0.0, 0.0};
  if (options.penetration && impact.penetration) {
    const double r = (penetration_sim_m - *impact.penetration) / d[0];
    t[0] = r * r;
  }
  if (options.contact_duration && impact.contact_duration) {
    const double r = (contact_duration_sim_s - *impact.contact_duration) / d[1];
    t[1] = r * r;
  }
  return t;
}

double noise_threshold(const Vel3& measured, const Vel3& sigma, const ErrorOptions& options) {
  const Vel3 d = error_scale(measured, options);
  double delta = 0;
  for (int k = 0; k < 3; ++k) delta += (sigma[k] / d[k]) * (sigma[k] / d[k]);
  return delta;
}

double contact_noise_threshold(const Impact& impact, double sigma_penetration_m,
                               double sigma_contact_duration_s, const ErrorOptions& options) {
  const std::array<double, 2> d = contact_error_scale(impact, options);
  double delta = 0;
  if (options.penetration && impact.penetration) {
    const double r = sigma_penetration_m / d[0];
    delta += r * r;
  }
  if (options.contact_duration && impact.contact_duration) {
    const double r = sigma_contact_duration_s / d[1];
    delta += r * r;
  }
  return delta;
}

}  // namespace ricochet::fit
