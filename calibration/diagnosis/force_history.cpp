// The force-history error of a calibrated model and the discovered law as a model
// (force_history.hpp).
#include "diagnosis/force_history.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "effects/force_term.hpp"

namespace ricochet::diagnosis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Sums of squared residuals and sample counts per component.
struct Squares {
  std::array<double, kForceComponents> sum{};
  std::array<std::size_t, kForceComponents> n{};
  void add(const ReleaseResidual& r) {
    for (const auto& row : r.residual)
      for (std::size_t c = 0; c < kForceComponents; ++c)
        if (std::isfinite(row[c])) {
          sum[c] += row[c] * row[c];
          ++n[c];
        }
  }
  void add(const Squares& o) {
    for (std::size_t c = 0; c < kForceComponents; ++c) {
      sum[c] += o.sum[c];
      n[c] += o.n[c];
    }
  }
  std::array<double, kForceComponents> rms() const {
    std::array<double, kForceComponents> out;
    for (std::size_t c = 0; c < kForceComponents; ++c)
      out[c] = n[c] > 0 ? std::sqrt(sum[c] / static_cast<double>(n[c])) : kNaN;
    return out;
  }
};

}  // namespace

ForceHistoryError force_history_error(const Model& model, const Shape& shape, const Assessment& a,
                                      const std::vector<std::optional<MeasuredHistory>>& histories,
                                      const EngineOptions& engine) {
  if (histories.size() != a.cv.n)
    throw std::invalid_argument(
        fmt::format("force_history_error: {} histories for a set of {}", histories.size(), a.cv.n));
  if (a.fold_params.size() != a.cv.splits())
    throw std::invalid_argument("force_history_error: the assessment has no fold fits");
  ForceHistoryError e;
  e.releases = history_count(histories);
  Squares in;
  for (const auto& h : histories)
    if (h) {
      const ReleaseResidual r = force_residual(*h, model, shape, a.population.params, engine);
      e.samples += r.samples.size();
      in.add(r);
    }
  // The splits are independent: each evaluates its own fit along its own test releases.
  std::vector<Squares> per_split(a.cv.splits());
#pragma omp parallel for schedule(dynamic)
  for (std::size_t s = 0; s < a.cv.splits(); ++s)
    for (std::size_t i : a.cv.test[s])
      if (histories[i])
        per_split[s].add(force_residual(*histories[i], model, shape, a.fold_params[s], engine));
  Squares out;
  for (const Squares& s : per_split) out.add(s);
  e.insample_rms = in.rms();
  e.heldout_rms = out.rms();
  return e;
}

nlohmann::json to_json(const ForceHistoryError& e) {
  const auto by_component = [](const std::array<double, kForceComponents>& v) {
    nlohmann::json j = nlohmann::json::object();
    for (std::size_t c = 0; c < kForceComponents; ++c)
      j[std::string(component_name(static_cast<ForceComponent>(c)))] =
          std::isfinite(v[c]) ? nlohmann::json(v[c]) : nlohmann::json(nullptr);
    return j;
  };
  return {{"insample_rms", by_component(e.insample_rms)},
          {"heldout_rms", by_component(e.heldout_rms)},
          {"releases", e.releases},
          {"samples", e.samples}};
}

Model with_force_law(const Model& base, std::span<const double> base_params,
                     const ForceLawReport& report, std::vector<std::string>* warnings) {
  Model m = base;
  if (!base_params.empty()) m.set_values({base_params.begin(), base_params.end()});
  for (const ComponentLaw& law : report.laws)
    for (const DiscoveredTerm& t : law.terms) {
      if (!t.selected) continue;
      const std::string effect = effects::force_term_effect_name(*t.term);
      const std::string name = effects::force_term_parameter_name(*t.term);
      Model with = m.with_effect(effect, /*at_neutral=*/true);
      const std::size_t i = with.index(name);
      const double v = std::clamp(t.coefficient, with.lower(i), with.upper(i));
      // Clamped to its neutral 0 (a negative drag or hysteresis) the term would do nothing:
      // it is left out rather than carried at zero.
      if (v != t.coefficient && warnings)
        warnings->push_back(fmt::format(
            "{} = {:.4g} {} is outside [{:.4g}, {:.4g}]: {} (effects/force_term.hpp: a negative "
            "drag or hysteresis would make energy)",
            name, t.coefficient, t.term->unit, with.lower(i), with.upper(i),
            v == 0.0 ? std::string("left out") : fmt::format("written as {:.4g}", v)));
      if (v == 0.0) continue;
      with.set(name, v);
      with.set_calibrated(name, false);  // the histories identify it, not the rebounds
      m = std::move(with);
    }
  return m;
}

}  // namespace ricochet::diagnosis
