#include "engine/engine.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "common/error.hpp"
#include "engine/lane_batch.hpp"

namespace ricochet {

const char* status_name(CollisionStatus status) {
  switch (status) {
    case CollisionStatus::kOk:
      return "ok";
    case CollisionStatus::kNoRebound:
      return "no_rebound";
    case CollisionStatus::kNoContact:
      return "no_contact";
  }
  return "?";
}

namespace {

using engine_internal::LaneBatch;
using engine_internal::Layout;

template <bool kDisc, bool kFlat>
void run_block(const Layout& layout, const Shape& shape, const EngineOptions& options,
               std::span<const CollisionCase> cases, std::span<const double> params, bool broadcast,
               CollisionResult* results, Trace* trace) {
  LaneBatch<kDisc, kFlat> batch(layout, shape, options, cases, params, broadcast, results, trace);
  batch.run();
}

void dispatch(const Layout& layout, const Shape& shape, const EngineOptions& options,
              std::span<const CollisionCase> cases, std::span<const double> params, bool broadcast,
              CollisionResult* results, Trace* trace) {
  const bool disc = shape.is_disc(), flat = options.ground.flat();
  if (disc && flat)
    run_block<true, true>(layout, shape, options, cases, params, broadcast, results, trace);
  else if (disc)
    run_block<true, false>(layout, shape, options, cases, params, broadcast, results, trace);
  else if (flat)
    run_block<false, true>(layout, shape, options, cases, params, broadcast, results, trace);
  else
    run_block<false, false>(layout, shape, options, cases, params, broadcast, results, trace);
}

// `consumer` names the entry point in the refusal of bad options (require_valid).
void validate(const Model& model, const Shape& shape, const EngineOptions& options,
              std::span<const CollisionCase> cases, std::span<const double> params,
              const char* consumer) {
  require_valid(options.problems(), consumer);
  const auto check_dt = [&](std::span<const double> row) {
    const double limit = critical_time_step(model, shape, row);
    // An option out of its range for these parameters: an InputError naming the option, as
    // require_valid's, so that every command exits with the input-error status.
    if (options.dt_s > limit)
      throw InputError("<options of " + std::string(consumer) + ">", 0, "dt_s",
                       fmt::format("the time step {:g} s exceeds the stability limit {:g} s of the "
                                   "model's stiffest spring at these parameters; use a smaller one",
                                   options.dt_s, limit));
  };
  const std::size_t P = model.parameter_count();
  if (!(shape.mass_kg > 0.0 && shape.inertia_kgm2 > 0.0 && shape.rounding_radius_m > 0.0))
    throw std::invalid_argument("shape '" + shape.name + "' needs mass, inertia and radius > 0");
  if (params.size() != P && params.size() != P * cases.size())
    throw std::invalid_argument("parameter array has " + std::to_string(params.size()) +
                                " values; expected " + std::to_string(P) + " or " +
                                std::to_string(P * cases.size()));
  std::vector<double> row(P);
  for (std::size_t k = 0; k * P < params.size(); ++k) {
    std::copy_n(params.data() + k * P, P, row.data());
    model.check(row);
    check_dt(row);
  }
  for (const auto& c : cases)
    for (double v : c.vin)
      if (!std::isfinite(v)) throw std::invalid_argument("incident velocity is not finite");
}

}  // namespace

double critical_time_step(const Model& model, const Shape& shape, std::span<const double> params) {
  const double rb = shape.bounding_radius();
  const double m_eff = 1.0 / (1.0 / shape.mass_kg + rb * rb / shape.inertia_kgm2);
  // Coefficient effects may stiffen the normal contact (hertz_stiffness, a generated law of kn):
  // their largest loading factor at a penetration up to the block's bounding radius, which no
  // rebound reaches.
  // Force terms add a spring of their own (a discovered c h^2): its stiffness adds to kn's.
  double kn_factor = 1.0, added_N_per_m = 0.0;
  const auto& effects = model.effects();
  for (std::size_t e = 0; e < effects.size(); ++e) {
    const auto values = params.subspan(model.offset(e), effects[e]->parameters().size());
    kn_factor *= effects[e]->max_stiffness_factor(values, rb);
    added_N_per_m += effects[e]->max_added_stiffness(values, rb);
  }
  double omega = 0.0;
  for (std::size_t i = 0; i < model.parameter_count(); ++i) {
    switch (model.spec(i).role) {
      case ParameterRole::kNormalStiffness:
        omega = std::max(omega, std::sqrt((params[i] * kn_factor + added_N_per_m) / m_eff));
        break;
      case ParameterRole::kTangentialStiffness:
        omega = std::max(omega, std::sqrt(params[i] / m_eff));
        break;
      case ParameterRole::kRollingStiffness:
        omega = std::max(omega, std::sqrt(params[i] / shape.inertia_kgm2));
        break;
      default:
        break;
    }
  }
  return omega > 0.0 ? 2.0 / omega : INFINITY;
}

namespace {
std::atomic<std::uint64_t> g_collisions{0};
}  // namespace

std::uint64_t collisions_simulated() {
  return g_collisions.load(std::memory_order_relaxed);
}

CollisionResult simulate(const Model& model, const Shape& shape, const CollisionCase& collision,
                         std::span<const double> params, const EngineOptions& options,
                         Trace* trace) {
  if (params.empty()) params = model.values();
  std::span<const CollisionCase> cases(&collision, 1);
  validate(model, shape, options, cases, params, "simulate");
  g_collisions.fetch_add(1, std::memory_order_relaxed);
  const Layout layout(model);
  CollisionResult result;
  dispatch(layout, shape, options, cases, params, true, &result, trace);
  return result;
}

std::vector<CollisionResult> simulate_batch(const Model& model, const Shape& shape,
                                            std::span<const CollisionCase> cases,
                                            std::span<const double> params,
                                            const EngineOptions& options) {
  if (params.empty()) params = model.values();
  validate(model, shape, options, cases, params, "simulate_batch");
  g_collisions.fetch_add(cases.size(), std::memory_order_relaxed);
  const Layout layout(model);
  const std::size_t P = model.parameter_count();
  const bool broadcast = params.size() == P && !(cases.size() == 1 && P == 0);
  std::vector<CollisionResult> results(cases.size());
  // Blocks of several lane-widths: enough blocks to balance two or more threads, large enough
  // that lanes stay full until the end of each block.
  const std::size_t lanes = std::max<std::size_t>(1, options.lanes);
  const std::size_t block = lanes * 8;
  const std::size_t nblocks = (cases.size() + block - 1) / block;
  // No more threads than blocks, and none from inside a parallel region (the fit module and the
  // diagnosis already run their searches on every core): a small batch in a team of two made
  // the leak-free lab-cylinder diagnosis 1.6 x slower than one thread (4.8 s against 3.0 s,
  // the idle and nested threads spinning on two cores).
  const int threads = static_cast<int>(std::min<std::size_t>(
      nblocks,
      static_cast<std::size_t>(options.threads > 0 ? options.threads : omp_get_max_threads())));
#pragma omp parallel for schedule(dynamic, 1) \
    num_threads(threads) if (threads > 1 && !omp_in_parallel())
  for (std::size_t b = 0; b < nblocks; ++b) {
    const std::size_t begin = b * block, end = std::min(cases.size(), begin + block);
    const auto sub = cases.subspan(begin, end - begin);
    const auto sub_params = broadcast ? params : params.subspan(begin * P, (end - begin) * P);
    dispatch(layout, shape, options, sub, sub_params, broadcast, results.data() + begin, nullptr);
  }
  return results;
}

}  // namespace ricochet
