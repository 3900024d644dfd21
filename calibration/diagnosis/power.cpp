#include "diagnosis/power.hpp"

#include <fmt/format.h>

#include <cmath>

namespace ricochet::diagnosis::detail {
namespace {

constexpr double kPower = 0.8;
constexpr double kZPower = 0.8416212335729143;  // standard normal quantile at 0.8

}  // namespace

std::vector<Detectable> minimum_detectable(
    const Directions& dirs, const std::vector<std::string>& names,
    const std::vector<std::optional<Model>>& models, const std::vector<Score>& scores,
    const stats::ScoreTests& tests, const EffectRegistry& registry,
    const std::array<bool, kObservables>& use, double alpha) {
  const double level = alpha / 2;  // the score route's share of the family-wise level
  const double c = stats::max_null_quantile(tests, level);
  std::vector<std::optional<Detectable>> best(kFamilyCount);
  if (!std::isfinite(c) || !(tests.dof > 0)) return {};
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
      const double beta = (c + kZPower) * sigma_s / s2;  // |change| from neutral
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
      d.unit = std::string(m.spec(j).unit);
      d.neutral = neutral;
      d.power = kPower;
      d.level = level;
      d.critical = c;
      d.noise_units = std::sqrt(s2 / n) * beta;
      const bool within = value >= m.lower(j) && value <= m.upper(j);
      d.value = within ? value : NAN;
      if (within) {
        std::vector<double> values = m.values();
        values[j] = value;
        d.law = law_of(m, values, {names[h]}, registry);
      } else {
        d.law = fmt::format("not detectable within its bounds [{:.4g}, {:.4g}] {}", m.lower(j),
                            m.upper(j), d.unit);
      }
      d.shift = rms_per_observable(dirs, dir.raw * static_cast<double>(side) * beta, use);
      auto& slot = best[static_cast<std::size_t>(kind.family)];
      // A law within its bounds beats one beyond them; then the smaller change in noise units.
      const bool better = !slot || (std::isfinite(d.value) && !std::isfinite(slot->value)) ||
                          (std::isfinite(d.value) == std::isfinite(slot->value) &&
                           d.noise_units < slot->noise_units);
      if (better) slot = std::move(d);
    }
  }
  std::vector<Detectable> out;
  for (auto& b : best)
    if (b) out.push_back(std::move(*b));
  return out;
}

}  // namespace ricochet::diagnosis::detail
