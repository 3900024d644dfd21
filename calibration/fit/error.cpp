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

double noise_threshold(const Vel3& measured, const Vel3& sigma, const ErrorOptions& options) {
  const Vel3 d = error_scale(measured, options);
  double delta = 0;
  for (int k = 0; k < 3; ++k) delta += (sigma[k] / d[k]) * (sigma[k] / d[k]);
  return delta;
}

}  // namespace ricochet::fit
