// The words of an effect's declaration (effect.hpp): the one table of each vocabulary, which the
// registry, `ricochet effects`, the diagnosis's trends and the tests all read.
#include "effects/effect.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

namespace ricochet {
namespace {

constexpr std::array<std::string_view, kParameterRoleCount> kRoleNames = {
    "other",       "normal_stiffness", "tangential_stiffness", "rolling_stiffness",
    "restitution", "friction_cap",     "rolling_cap",          "drag_coefficient"};

constexpr std::array<std::string_view, kIdentifiedByCount> kIdentifiedByNames = {
    "rebound", "contact_features", "nothing"};

constexpr std::array<std::string_view, kResidualQuantityCount + 1> kQuantityNames = {
    "residual vx", "residual vy", "residual w", "residual penetration", "residual contact_duration",
    "param"};

constexpr std::array<std::string_view, kImpactFeatureCount> kFeatureNames = {
    "speed_in",     "abs_vin_y", "vin_x",       "win",
    "impact_angle", "alpha_in",  "penetration", "contact_duration"};

// The word of an enum value in its table; "?" for a value outside it (a cast, or a plugin built
// against a newer header: the registry refuses those).
template <std::size_t N, class E>
std::string_view word_of(const std::array<std::string_view, N>& words, E value) {
  const auto i = static_cast<std::size_t>(value);
  return i < N ? words[i] : "?";
}

template <std::size_t N>
std::string join(const std::array<std::string_view, N>& words, std::size_t from = 0) {
  std::string s;
  for (std::size_t i = from; i < N; ++i) s += (s.empty() ? "" : ", ") + std::string(words[i]);
  return s;
}

// "residual vx, ..., residual contact_duration, param <role> with role in {...}".
std::string known_quantities() {
  std::string s;
  for (std::size_t i = 0; i < kResidualQuantityCount; ++i)
    s += std::string(kQuantityNames[i]) + ", ";
  return s + "param <role> with role in {" + join(kRoleNames, 1) + "}";
}

}  // namespace

std::string_view stage_name(Stage stage) {
  static constexpr std::array<std::string_view, kStageCount> kNames = {
      "coefficient", "normal", "tangential", "rolling", "body"};
  return word_of(kNames, stage);
}

std::string_view family_name(Family family) {
  static constexpr std::array<std::string_view, kFamilyCount> kNames = {
      "none",      "restitution", "sliding_friction", "rolling_resistance",
      "stiffness", "drag",        "ploughing",        "other"};
  return word_of(kNames, family);
}

std::string_view variable_name(Variable variable) {
  static constexpr std::array<std::string_view, kVariableCount> kNames = {
      "none", "impact_speed", "normal_speed",    "penetration",
      "spin", "slip_speed",   "incidence_angle", "other"};
  return word_of(kNames, variable);
}

std::string_view role_name(ParameterRole role) {
  return word_of(kRoleNames, role);
}

std::string_view identified_by_name(IdentifiedBy by) {
  return word_of(kIdentifiedByNames, by);
}

std::string_view quantity_name(TrendQuantity quantity) {
  return word_of(kQuantityNames, quantity);
}

std::string_view feature_name(ImpactFeature feature) {
  return word_of(kFeatureNames, feature);
}

ExpectedTrend parse_trend(const SignatureTrend& trend) {
  ExpectedTrend out;
  bool quantity = false;
  for (std::size_t i = 0; i < kResidualQuantityCount && !quantity; ++i)
    if (trend.quantity == kQuantityNames[i]) {
      out.quantity = static_cast<TrendQuantity>(i);
      quantity = true;
    }
  constexpr std::string_view kParam = "param ";
  if (!quantity && trend.quantity.starts_with(kParam)) {
    const std::string_view role = trend.quantity.substr(kParam.size());
    for (std::size_t r = 1; r < kRoleNames.size() && !quantity; ++r)  // "other" names nothing
      if (role == kRoleNames[r]) {
        out.quantity = TrendQuantity::kParameter;
        out.parameter = static_cast<ParameterRole>(r);
        quantity = true;
      }
  }
  if (!quantity)
    throw std::invalid_argument("unknown signature quantity '" + std::string(trend.quantity) +
                                "'; known quantities: " + known_quantities());
  for (std::size_t i = 0; i < kFeatureNames.size(); ++i)
    if (trend.feature == kFeatureNames[i]) {
      out.feature = static_cast<ImpactFeature>(i);
      return out;
    }
  throw std::invalid_argument("unknown signature feature '" + std::string(trend.feature) +
                              "'; known features: " + join(kFeatureNames));
}

std::array<ParameterRole, 2> fused_law_roles(FusedLaw law) {
  switch (law) {
    case FusedLaw::kPaperNormal:
      return {ParameterRole::kNormalStiffness, ParameterRole::kRestitution};
    case FusedLaw::kPaperTangential:
      return {ParameterRole::kTangentialStiffness, ParameterRole::kFrictionCap};
    case FusedLaw::kPaperRolling:
      return {ParameterRole::kRollingStiffness, ParameterRole::kRollingCap};
    case FusedLaw::kNone:
      break;
  }
  return {ParameterRole::kOther, ParameterRole::kOther};
}

std::string Effect::law(std::span<const double> values) const {
  std::string out(equation());
  const auto specs = parameters();
  for (std::size_t i = 0; i < specs.size() && i < values.size(); ++i) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4g", values[i]);
    // Appended piece by piece: `", " + std::string(...)` trips GCC 12's -Wrestrict false
    // positive.
    out.append(", ").append(specs[i].name).append(" = ").append(buf);
    if (specs[i].unit != "-") out.append(" ").append(specs[i].unit);
  }
  return out;
}

}  // namespace ricochet
