#include "diagnosis/power.hpp"

#include <fmt/format.h>

#include <cmath>

namespace ricochet::diagnosis::detail {
namespace {

constexpr double kPower = 0.8;
constexpr double kZPower = 0.8416212335729143;  // standard normal quantile at 0.8

}  // namespace

std::vector<Detectable> detectable_candidates(
    const Directions& dirs, const std::vector<std::string>& names,
    const std::vector<std::optional<Model>>& models, const std::vector<Score>& scores,
    const stats::ScoreTests& tests, const EffectRegistry& registry,
    const std::array<bool, kObservables>& use, double alpha) {
  const double level = alpha / 2;  // the score route's share of the family-wise level
  const double c = stats::max_null_quantile(tests, level);
  std::vector<Detectable> rows;
  if (!std::isfinite(c) || !(tests.dof > 0)) return rows;
  for (std::size_t h = 0; h < names.size(); ++h) {
    if (!models[h]) continue;
    const Score& sc = scores[h];
    const LawKind kind = registry.get(names[h]).kind();
    for (std::size_t col = 0; col < sc.directions.size() && col < sc.columns.size(); ++col) {
      const ScoreDirection& dir = sc.directions[col];
      const std::vector<double>& u = sc.columns[col].u;
      const auto n = static_cast<double>(u.size());
      const double sigma_s = stats::score_standard_error(u, tests.dof);
      const double s2 = dir.s.squaredNorm();
      if (!(sigma_s > 0) || !(s2 > 0)) continue;
      // Per release, the score's gain per unit change: a_i = |s_i|^2 over its rows.
      const std::vector<double> a = per_release_products(dirs, dir.s, dir.s, u.size());
      const double spread = stats::score_standard_error(a, tests.dof);  // sqrt(V)
      const double k = c + kZPower;
      // T(beta) = beta A / sqrt(sigma_S^2 + beta^2 V) = k  (file comment); none when the
      // ceiling A / sqrt(V) is below k.
      const double room = s2 * s2 - k * k * spread * spread;
      const double beta = room > 0 ? k * sigma_s / std::sqrt(room) : INFINITY;
      const int side = dir.allowed != 0 ? dir.allowed : 1;
      const Model& m = *models[h];
      const std::size_t j = dir.parameter;
      const double neutral = m.values()[j];
      const double value = neutral + side * beta;
      Detectable d;
      d.family = kind.family;
      d.effect = names[h];
      d.variable = kind.variable;
      d.parameter = std::string(m.spec(j).name);
      d.change_80 = side * beta;
      d.t_per_unit = s2 / sigma_s;
      d.t_ceiling = spread > 0 ? s2 / spread : INFINITY;
      d.unit = std::string(m.spec(j).unit);
      d.neutral = neutral;
      d.power = kPower;
      d.level = level;
      d.critical = c;
      d.noise_units = std::sqrt(s2 / n) * beta;
      const bool within = std::isfinite(beta) && value >= m.lower(j) && value <= m.upper(j);
      d.value = within ? value : NAN;
      if (within) {
        std::vector<double> values = m.values();
        values[j] = value;
        d.law = law_of(m, values, {names[h]}, registry);
      } else if (std::isfinite(beta)) {
        d.law = fmt::format("not detectable within its bounds [{:.4g}, {:.4g}] {}", m.lower(j),
                            m.upper(j), d.unit);
      } else {
        d.law = fmt::format(
            "not detectable at any strength: its statistic's ceiling {:.3g} (the law's change "
            "varies from release to release as much as the score grows) is below {:.3g}",
            d.t_ceiling, k);
      }
      d.shift = std::isfinite(beta)
                    ? rms_per_observable(dirs, dir.raw * static_cast<double>(side) * beta, use)
                    : Obs{NAN, NAN, NAN, NAN, NAN};
      rows.push_back(std::move(d));
    }
  }
  return rows;
}

std::vector<Detectable> minimum_detectable(const std::vector<Detectable>& candidates) {
  std::vector<std::optional<Detectable>> best(kFamilyCount);
  for (const Detectable& d : candidates) {
    auto& slot = best[static_cast<std::size_t>(d.family)];
    // A law within its bounds beats one beyond them; then the smaller change in noise units.
    const bool better =
        !slot || (std::isfinite(d.value) && !std::isfinite(slot->value)) ||
        (std::isfinite(d.value) == std::isfinite(slot->value) && d.noise_units < slot->noise_units);
    if (better) slot = d;
  }
  std::vector<Detectable> out;
  for (auto& b : best)
    if (b) out.push_back(std::move(*b));
  return out;
}

}  // namespace ricochet::diagnosis::detail
