#include "diagnosis/trends.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "common/json_number.hpp"
#include "stats/stats.hpp"

namespace ricochet::diagnosis {

std::vector<Feature> impact_features(const ImpactSet& set,
                                     const std::vector<ObsPrediction>& insample,
                                     const std::vector<double>& alpha_fitted) {
  const std::size_t n = set.size();
  std::vector<Feature> out;
  // Named in the signature vocabulary's words (effects/effect.hpp), which effects declare.
  auto add = [&](ImpactFeature feature, std::string label, bool simulated, auto value) {
    Feature f{std::string(feature_name(feature)), std::move(label), simulated,
              std::vector<double>(n)};
    for (std::size_t i = 0; i < n; ++i) f.values[i] = value(i);
    out.push_back(std::move(f));
  };
  const auto& im = set.impacts;
  using F = ImpactFeature;
  add(F::kSpeedIn, "|V_in| [m/s]", false,
      [&](std::size_t i) { return std::hypot(im[i].vin[0], im[i].vin[1]); });
  add(F::kAbsVinY, "|V_in^y| [m/s]", false, [&](std::size_t i) { return std::fabs(im[i].vin[1]); });
  add(F::kVinX, "V_in^x [m/s]", false, [&](std::size_t i) { return im[i].vin[0]; });
  add(F::kWin, "omega_in [rad/s]", false, [&](std::size_t i) { return im[i].vin[2]; });
  // Incidence angle of the velocity below the horizontal (90 deg = vertical fall).
  add(F::kImpactAngle, "incidence angle of V_in [deg]", false,
      [&](std::size_t i) { return std::atan2(-im[i].vin[1], im[i].vin[0]) * 180.0 / M_PI; });
  const bool has_alpha = !im.empty() && std::all_of(im.begin(), im.end(), [](const Impact& x) {
    return x.alpha_in.has_value();
  });
  if (has_alpha) {
    add(F::kAlphaIn, "alpha_in [deg]", false,
        [&](std::size_t i) { return *im[i].alpha_in * 180.0 / M_PI; });
  } else if (alpha_fitted.size() == n && std::any_of(alpha_fitted.begin(), alpha_fitted.end(),
                                                     [](double a) { return std::isfinite(a); })) {
    add(F::kAlphaIn, "alpha_in (fitted per release) [deg]", true,
        [&](std::size_t i) { return alpha_fitted[i] * 180.0 / M_PI; });
  }
  const bool has_h = !im.empty() && std::all_of(im.begin(), im.end(), [](const Impact& x) {
    return x.penetration.has_value();
  });
  const bool has_t = !im.empty() && std::all_of(im.begin(), im.end(), [](const Impact& x) {
    return x.contact_duration.has_value();
  });
  if (has_h)
    add(F::kPenetration, "penetration [mm]", false,
        [&](std::size_t i) { return *im[i].penetration * 1e3; });
  else if (insample.size() == n)
    add(F::kPenetration, "penetration (simulated) [mm]", true,
        [&](std::size_t i) { return insample[i].value[kObsPenetration] * 1e3; });
  if (has_t)
    add(F::kContactDuration, "contact duration [ms]", false,
        [&](std::size_t i) { return *im[i].contact_duration * 1e3; });
  else if (insample.size() == n)
    add(F::kContactDuration, "contact duration (simulated) [ms]", true,
        [&](std::size_t i) { return insample[i].value[kObsDuration] * 1e3; });
  return out;
}

namespace {

// Ranks (1-based, ties averaged) of the finite values; NaN stays NaN.
std::vector<double> ranks(const std::vector<double>& x) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (std::isfinite(x[i])) idx.push_back(i);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  std::vector<double> r(x.size(), NAN);
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i;
    while (j + 1 < idx.size() && x[idx[j + 1]] == x[idx[i]]) ++j;
    const double avg = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) r[idx[k]] = avg;
    i = j + 1;
  }
  return r;
}

Trend correlate(const std::string& quantity, const std::string& label, const Feature& f,
                const std::vector<double>& y, const TrendOptions& o) {
  Trend t;
  t.quantity = quantity;
  t.label = label;
  t.feature = f.name;
  t.feature_label = f.label;
  const stats::Correlation c = stats::pearson(f.values, y);
  t.r = c.r;
  t.p = c.p_value;
  t.n = c.n;
  // Spearman on the pairs where both values exist.
  std::vector<double> xs, ys;
  for (std::size_t i = 0; i < y.size(); ++i)
    if (std::isfinite(y[i]) && std::isfinite(f.values[i]))
      xs.push_back(f.values[i]), ys.push_back(y[i]);
  const stats::Correlation s = stats::pearson(ranks(xs), ranks(ys));
  t.rho = s.r;
  t.p_rank = s.p_value;
  (void)o;  // significance is decided over the family (control_family)
  return t;
}

// A feature label without its unit, for sentences.
std::string bare(const std::string& label) {
  const auto k = label.find(" [");
  return k == std::string::npos ? label : label.substr(0, k);
}

}  // namespace

std::vector<Trend> residual_trends(const ErrorReport& report,
                                   const std::array<bool, kObservables>& use,
                                   const std::vector<Feature>& features, const TrendOptions& o) {
  std::vector<Trend> out;
  for (int k = 0; k < kObservables; ++k) {
    if (!use[k]) continue;
    std::vector<double> y(report.residual.size());
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = report.residual[i][k];
    for (const auto& f : features) {
      // The residual of a measured feature against the same feature is trivially correlated.
      if ((k == kObsPenetration && f.name == feature_name(ImpactFeature::kPenetration) &&
           !f.simulated) ||
          (k == kObsDuration && f.name == feature_name(ImpactFeature::kContactDuration) &&
           !f.simulated))
        continue;
      out.push_back(correlate(residual_quantity(k), std::string(kObservableLabels[k]) + " residual",
                              f, y, o));
    }
  }
  control_family({&out}, o.alpha);
  return out;
}

std::vector<Trend> parameter_trends(const std::vector<fit::ReleaseFit>& fits,
                                    const std::vector<Feature>& features, const TrendOptions& o) {
  std::vector<Trend> out;
  if (fits.empty()) return out;
  for (std::size_t c : fits.front().calibrated) {
    const std::string name = fits.front().names[c];
    std::vector<double> y(fits.size(), NAN);
    for (std::size_t i = 0; i < fits.size(); ++i) {
      const fit::ParameterInterval* iv = fits[i].interval(name);
      const bool ok = !iv || iv->status == fit::Identifiability::kIdentified;
      if (ok) y[i] = fits[i].params[c];
    }
    for (const auto& f : features)
      out.push_back(correlate(parameter_quantity(name), "calibrated " + name, f, y, o));
  }
  control_family({&out}, o.alpha);
  return out;
}

// The signature vocabulary lists the residuals in the observables' order.
static_assert(static_cast<int>(TrendQuantity::kResidualVx) == kObsVx &&
              static_cast<int>(TrendQuantity::kResidualVy) == kObsVy &&
              static_cast<int>(TrendQuantity::kResidualW) == kObsW &&
              static_cast<int>(TrendQuantity::kResidualPenetration) == kObsPenetration &&
              static_cast<int>(TrendQuantity::kResidualContactDuration) == kObsDuration &&
              kResidualQuantityCount == kObservables);

std::string residual_quantity(int observable) {
  return std::string(quantity_name(static_cast<TrendQuantity>(observable)));
}

std::string parameter_quantity(const std::string& name) {
  return std::string(quantity_name(TrendQuantity::kParameter)) + " " + name;
}

void control_family(const std::vector<std::vector<Trend>*>& groups, double alpha) {
  std::vector<Trend*> all;
  for (auto* g : groups)
    for (auto& t : *g) all.push_back(&t);
  std::vector<double> p, q;
  for (const Trend* t : all) {
    p.push_back(std::isfinite(t->p) ? t->p : NAN);
    q.push_back(std::isfinite(t->p_rank) ? t->p_rank : NAN);
  }
  const std::vector<double> hp = stats::holm_adjust(p), hq = stats::holm_adjust(q);
  for (std::size_t i = 0; i < all.size(); ++i) {
    Trend& t = *all[i];
    t.p_holm = hp[i];
    t.p_rank_holm = hq[i];
    t.significant = std::isfinite(t.r) && std::isfinite(hp[i]) && hp[i] < alpha &&
                    std::isfinite(hq[i]) && hq[i] < alpha && t.rho * t.r > 0;
  }
}

const Trend* find_trend(const std::vector<Trend>& trends, const std::string& quantity,
                        const std::string& feature) {
  for (const auto& t : trends)
    if (t.quantity == quantity && t.feature == feature) return &t;
  return nullptr;
}

std::string describe(const Trend& t) {
  return fmt::format(
      "{} {} with {} (r = {:.2f}, p = {:.2g}, Holm-adjusted {:.2g}; rank rho = {:.2f}; n = {})",
      t.label, t.r >= 0 ? "grows" : "falls", bare(t.feature_label), t.r, t.p, t.p_holm, t.rho, t.n);
}

nlohmann::json to_json(const Trend& t) {
  return {{"quantity", t.quantity},
          {"feature", t.feature},
          {"feature_label", t.feature_label},
          {"r", finite_or_null(t.r)},
          {"p", finite_or_null(t.p)},
          {"rho", finite_or_null(t.rho)},
          {"p_rank", finite_or_null(t.p_rank)},
          {"p_holm", finite_or_null(t.p_holm)},
          {"n", t.n},
          {"significant", t.significant},
          {"text", describe(t)}};
}

nlohmann::json to_json(const std::vector<Trend>& trends, bool significant_only) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& t : trends)
    if (!significant_only || t.significant) j.push_back(to_json(t));
  return j;
}

}  // namespace ricochet::diagnosis
