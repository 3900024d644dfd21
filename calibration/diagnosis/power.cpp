#include "diagnosis/power.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "common/progress.hpp"

namespace ricochet::diagnosis::detail {
namespace {

constexpr double kPower = 0.8;
constexpr double kZPower = 0.8416212335729143;  // standard normal quantile at 0.8

// The score test's expected statistic with the candidate's law at a finite change (file
// comment, "At a finite strength"), and the change at which it reaches a target.
class StrengthCurve {
 public:
  StrengthCurve(const Directions& dirs, const ScoreDirection& dir, const Model& m,
                const Shape& shape, const ImpactSet& set, const std::vector<ObsPrediction>& p0,
                const AssessOptions& o, double sigma_s, double dof)
      : dirs_(dirs),
        dir_(dir),
        m_(m),
        shape_(shape),
        set_(set),
        p0_(p0),
        o_(o),
        sigma_s_(sigma_s),
        dof_(dof),
        side_(dir.allowed != 0 ? dir.allowed : 1) {}

  int side() const { return side_; }
  /// How far the parameter may move from neutral on its allowed side.
  double range() const {
    const std::size_t j = dir_.parameter;
    const double neutral = m_.values()[j];
    return side_ > 0 ? m_.upper(j) - neutral : neutral - m_.lower(j);
  }
  /// E[T] at the change side * beta (beta >= 0), recorded in points().
  double t(double beta) {
    const FiniteChange& g = change(beta);
    std::vector<double> a = per_release_products(dirs_, dir_.s, g.s, set_.size());
    double sum = 0;
    for (double& x : a) sum += (x *= side_);
    const double spread = stats::score_standard_error(a, dof_);
    const double t = sum / std::sqrt(sigma_s_ * sigma_s_ + spread * spread);
    points_.emplace_back(side_ * beta, t);
    return t;
  }
  /// The smallest beta in (0, range()] with t(beta) >= k, by doubling or halving from `start`
  /// and then bisection in log beta; NaN when t stays below k up to range().
  double solve(double k, double start) {
    const double top = range();
    if (!(top > 0)) return NAN;
    double b = std::isfinite(start) && start > 0 ? std::min(start, top) : top / 4;
    double lo = 0, hi = NAN;
    // Move b onto the target's side it is not on until the target is bracketed in [lo, hi].
    if (t(b) >= k) {
      hi = b;
      for (int i = 0; i < kSteps && lo == 0; ++i) {
        const double down = hi / 2;
        if (t(down) >= k)
          hi = down;
        else
          lo = down;
      }
      if (lo == 0) lo = hi / 2;  // still above at 1/64 of the start: close enough to zero
    } else {
      lo = b;
      while (std::isnan(hi) && lo < top) {
        const double up = std::min(2 * lo, top);
        if (t(up) >= k)
          hi = up;
        else
          lo = up;
      }
      if (std::isnan(hi)) return NAN;
    }
    for (int i = 0; i < kSteps; ++i) {
      const double mid = std::sqrt(lo * hi);
      if (t(mid) >= k)
        hi = mid;
      else
        lo = mid;
    }
    return hi;
  }
  /// The predictions' change at side * beta. Each strength is simulated once: the search
  /// ends on a strength it has evaluated, and the fixed points may repeat one of its brackets.
  const FiniteChange& change(double beta) {
    auto it = changes_.find(beta);
    if (it == changes_.end()) {
      std::vector<double> v = m_.values();
      v[dir_.parameter] += side_ * beta;
      it = changes_.emplace(beta, finite_change(dirs_, m_, shape_, set_, v, p0_, o_)).first;
    }
    return it->second;
  }
  std::vector<std::pair<double, double>> points() const {
    auto p = points_;
    std::sort(p.begin(), p.end(),
              [](const auto& x, const auto& y) { return std::fabs(x.first) < std::fabs(y.first); });
    return p;
  }

 private:
  static constexpr int kSteps = 6;
  const Directions& dirs_;
  const ScoreDirection& dir_;
  const Model& m_;
  const Shape& shape_;
  const ImpactSet& set_;
  const std::vector<ObsPrediction>& p0_;
  const AssessOptions& o_;
  double sigma_s_, dof_;
  int side_;
  std::vector<std::pair<double, double>> points_;
  std::map<double, FiniteChange> changes_;
};

}  // namespace

std::vector<Detectable> detectable_candidates(
    const Directions& dirs, const std::vector<std::string>& names,
    const std::vector<std::optional<Model>>& models, const std::vector<Score>& scores,
    const stats::ScoreTests& tests, const EffectRegistry& registry,
    const std::array<bool, kObservables>& use, double alpha, const Shape& shape,
    const ImpactSet& set, const AssessOptions& o, Progress* progress) {
  const double level = alpha / 2;  // the score route's share of the family-wise level
  const double c = stats::max_null_quantile(tests, level);
  std::vector<Detectable> rows;
  if (!std::isfinite(c) || !(tests.dof > 0)) return rows;
  const double k = c + kZPower;
  for (std::size_t h = 0; h < names.size(); ++h) {
    if (progress) progress->advance();
    if (!models[h]) continue;
    const Score& sc = scores[h];
    const LawKind kind = registry.get(names[h]).kind();
    const Model& m = *models[h];
    std::vector<ObsPrediction> p0;  // the candidate at neutral, once for its columns
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
      // The linear strength, T(beta) = beta A / sqrt(sigma_S^2 + beta^2 V) = k (file comment);
      // none when the ceiling A / sqrt(V) is below k. It starts the finite-strength search.
      const double room = s2 * s2 - k * k * spread * spread;
      const double linear = room > 0 ? k * sigma_s / std::sqrt(room) : INFINITY;
      if (p0.empty()) p0 = predict_observables(m, shape, m.values(), set, o);
      StrengthCurve curve(dirs, dir, m, shape, set, p0, o, sigma_s, tests.dof);
      const double beta = curve.solve(k, linear);
      // A few fixed points as well, so that the curve answers at any strength within the
      // bounds (the power of a given law, e.g. in the calibration study), not only near beta_80.
      for (int e = 0; e <= 6; e += 2) curve.t(curve.range() * std::ldexp(1.0, -e));
      const std::vector<std::pair<double, double>> points = curve.points();
      const int side = curve.side();
      const std::size_t j = dir.parameter;
      const double neutral = m.values()[j];
      Detectable d;
      d.family = kind.family;
      d.effect = names[h];
      d.variable = kind.variable;
      d.parameter = std::string(m.spec(j).name);
      d.t_per_unit = s2 / sigma_s;
      d.t_ceiling = spread > 0 ? s2 / spread : INFINITY;
      d.unit = std::string(m.spec(j).unit);
      d.neutral = neutral;
      d.power = kPower;
      d.level = level;
      d.critical = c;
      if (std::isfinite(beta)) {
        const double value = neutral + side * beta;
        const FiniteChange& g = curve.change(beta);
        d.change_80 = side * beta;
        d.value = value;
        std::vector<double> values = m.values();
        values[j] = value;
        d.law = law_of(m, values, {names[h]}, registry);
        d.z_80 = g.s.norm();
        d.noise_units = d.z_80 / std::sqrt(n);
        d.shift = rms_per_observable(dirs, g.raw, use);
      } else {
        // Beyond the bounds the linear strength is all there is to say how far (NaN value).
        d.change_80 = side * linear;
        const double at_bound = points.empty() ? NAN : points.back().second;
        d.law = fmt::format(
            "not detectable within its bounds [{:.4g}, {:.4g}] {}: at the bound its statistic's "
            "mean reaches {:.3g}, below {:.3g}",
            m.lower(j), m.upper(j), d.unit, at_bound, k);
        d.shift = Obs{NAN, NAN, NAN, NAN, NAN};
      }
      d.t_curve = points;
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
