// Deterministic space-filling designs of the unit hypercube (OpenTURNS), shared by the
// calibration starts (fit) and the Monte Carlo / range calibration (uq).
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

namespace ricochet::fit {

/// The lock every user of OpenTURNS' process-wide random generator holds while seeding and
/// drawing (fit and uq), so that concurrent callers cannot interleave draws.
std::mutex& openturns_rng_mutex();

/// Latin hypercube design of `n` points in [0, 1]^dim (OpenTURNS LHSExperiment), reproducible
/// from `seed`. Row-major: point i is [i * dim, (i + 1) * dim). Thread-safe (OpenTURNS' random
/// generator is global: calls are serialised and the generator is reseeded every call).
std::vector<double> lhs_unit_design(std::size_t dim, std::size_t n, std::uint64_t seed);

/// `n` independent uniform points in [0, 1]^dim (OpenTURNS RandomGenerator), reproducible from
/// `seed`; same layout and thread-safety as lhs_unit_design().
std::vector<double> uniform_unit_sample(std::size_t dim, std::size_t n, std::uint64_t seed);

}  // namespace ricochet::fit
