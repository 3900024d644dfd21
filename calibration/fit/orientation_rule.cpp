#include "fit/orientation_rule.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "fit/fit.hpp"

namespace ricochet::fit {

double release_rotation(std::string_view id) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64-bit offset basis
  for (unsigned char c : id) {
    h ^= c;
    h *= 1099511628211ull;  // FNV-1a 64-bit prime
  }
  // The top 53 bits as a double in [0, 1).
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

std::vector<double> orientation_rule(const AlphaOptions& alpha, int n, double r) {
  std::vector<double> g(static_cast<std::size_t>(std::max(1, n)));
  const double width = alpha.max_rad - alpha.min_rad;
  for (std::size_t k = 0; k < g.size(); ++k)
    g[k] = alpha.min_rad + width * (static_cast<double>(k) + r) / static_cast<double>(g.size());
  return g;
}

double RuleMean::error() const {
  return std::max(std::fabs(half[0] - mean), std::fabs(half[1] - mean));
}

RuleMean rule_mean(const std::vector<double>& values) {
  RuleMean m;
  const std::size_t n = values.size();
  if (n == 0) return m;
  std::array<double, 2> count{};
  for (std::size_t k = 0; k < n; ++k) {
    const double v = values[k];
    m.mean += v;
    m.mean_sq += v * v;
    const std::size_t h = n % 2 == 0 ? k % 2 : 0;
    m.half[h] += v;
    m.half_sq[h] += v * v;
    count[h] += 1;
  }
  m.mean /= static_cast<double>(n);
  m.mean_sq /= static_cast<double>(n);
  if (n % 2 != 0) {
    m.half = {m.mean, m.mean};
    m.half_sq = {m.mean_sq, m.mean_sq};
    return m;
  }
  for (int h = 0; h < 2; ++h) {
    m.half[h] /= count[h];
    m.half_sq[h] /= count[h];
  }
  return m;
}

}  // namespace ricochet::fit
