#include "fit/design.hpp"

#include <openturns/OT.hxx>

#include <mutex>

namespace ricochet::fit {
std::mutex& openturns_rng_mutex() {
  // OpenTURNS keeps one process-wide random generator: serialise its use so that concurrent
  // callers cannot interleave draws (which would break reproducibility).
  static std::mutex m;
  return m;
}

std::vector<double> lhs_unit_design(std::size_t dim, std::size_t n, std::uint64_t seed) {
  std::vector<double> out(dim * n);
  if (dim == 0 || n == 0) return out;
  std::lock_guard<std::mutex> lock(openturns_rng_mutex());
  OT::RandomGenerator::SetSeed(seed);
  const OT::ComposedDistribution unit(
      OT::ComposedDistribution::DistributionCollection(dim, OT::Uniform(0.0, 1.0)));
  OT::LHSExperiment lhs(unit, n);
  const OT::Sample s = lhs.generate();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < dim; ++k) out[i * dim + k] = s(i, k);
  return out;
}

std::vector<double> uniform_unit_sample(std::size_t dim, std::size_t n, std::uint64_t seed) {
  std::vector<double> out(dim * n);
  if (out.empty()) return out;
  std::lock_guard<std::mutex> lock(openturns_rng_mutex());
  OT::RandomGenerator::SetSeed(seed);
  const OT::Point p = OT::RandomGenerator::Generate(dim * n);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = p[i];
  return out;
}

}  // namespace ricochet::fit
