#include "fit/collision_memo.hpp"

#include <fmt/format.h>

#include <cstring>

#include "fit/fibers.hpp"

namespace ricochet::fit {
namespace {

// A collision's inputs as bytes: exact, so only a bit-identical collision is found.
std::string key_of(const CollisionCase& c, std::span<const double> row) {
  std::string k((4 + row.size()) * sizeof(double), '\0');
  char* p = k.data();
  std::memcpy(p, c.vin.data(), 3 * sizeof(double));
  std::memcpy(p + 3 * sizeof(double), &c.alpha_rad, sizeof(double));
  std::memcpy(p + 4 * sizeof(double), row.data(), row.size() * sizeof(double));
  return k;
}

}  // namespace

std::vector<CollisionResult> CollisionMemo::run(detail::Simulator& sim,
                                                std::span<const CollisionCase> cases,
                                                std::span<const double> params,
                                                std::size_t per_case) {
  std::vector<CollisionResult> out(cases.size());
  std::vector<std::string> keys(cases.size());
  std::vector<std::size_t> missing;
  {
    const std::lock_guard lock(mutex_);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      keys[i] = key_of(cases[i], params.subspan(i * per_case, per_case));
      const auto it = results_.find(keys[i]);
      if (it == results_.end()) {
        missing.push_back(i);
      } else {
        out[i] = it->second;
        ++hits_;
      }
    }
  }
  if (missing.empty()) return out;
  std::vector<CollisionCase> run_cases;
  std::vector<double> run_params;
  run_cases.reserve(missing.size());
  run_params.reserve(missing.size() * per_case);
  for (std::size_t i : missing) {
    run_cases.push_back(cases[i]);
    const auto row = params.subspan(i * per_case, per_case);
    run_params.insert(run_params.end(), row.begin(), row.end());
  }
  const std::vector<CollisionResult> res = sim.run(run_cases, run_params);
  const std::lock_guard lock(mutex_);
  for (std::size_t j = 0; j < missing.size(); ++j) {
    out[missing[j]] = res[j];
    results_.emplace(std::move(keys[missing[j]]), res[j]);
  }
  return out;
}

std::size_t CollisionMemo::hits() const {
  const std::lock_guard lock(mutex_);
  return hits_;
}

std::size_t CollisionMemo::stored() const {
  const std::lock_guard lock(mutex_);
  return results_.size();
}

std::string collision_memo_scope(const Model& model, const Shape& shape, const EngineOptions& e) {
  std::string s;
  for (const auto& name : model.effect_names()) s += name + ",";
  s += fmt::format("|{}|{:a}|{:a}|{:a}|{:a}|{}", shape.name, shape.mass_kg, shape.inertia_kgm2,
                   shape.rounding_radius_m, shape.length_m, shape.vertices.size());
  for (const auto& v : shape.vertices) s += fmt::format("|{:a},{:a}", v[0], v[1]);
  s += fmt::format("|{:a}|{:a}|{:a}|{:a}|{}", e.dt_s, e.max_time_s, e.gravity_mps2, e.initial_gap_m,
                   e.skip_flights);
  for (std::size_t i = 0; i < e.ground.x_m.size(); ++i)
    s += fmt::format("|{:a},{:a}", e.ground.x_m[i], e.ground.y_m[i]);
  return s;
}

}  // namespace ricochet::fit
