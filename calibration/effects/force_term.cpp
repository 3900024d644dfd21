// `term_<name>`: the force terms of the force-residual discovery as effects (force_term.hpp).
#include "effects/force_term.hpp"

#include <algorithm>
#include <cmath>

namespace ricochet::effects {

namespace {

double sgn(double x) {
  return x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0;
}

// The reference state and magnitudes of the bounds (file comment of force_term.hpp).
constexpr ContactSample kReference{.h_m = 3e-3,
                                   .vn_mps = -2.5,
                                   .vt_mps = 1.0,
                                   .vx_mps = 1.0,
                                   .omega_radps = 40.0,
                                   .loading = true};
constexpr double kForceRef_N = 3e4, kMomentRef_Nm = 2.4e3;

// What a missing term leaves in the rebounds (the diagnosis's words, effect.hpp), by what the
// term is: an elastic curve changes how deep and how long the contact is; a normal drag takes
// more of a faster landing; a hysteresis lowers the restitution more for a harder landing; the
// ploughing and a depth-growing friction hold back more the deeper the block goes; a sliding drag
// grows with the slip; a rolling term brakes the spin.
constexpr SignatureTrend kElastic[] = {{"residual penetration", "speed_in"},
                                       {"residual contact_duration", "speed_in"}};
constexpr SignatureTrend kNormalDrag[] = {{"residual vy", "speed_in"},
                                          {"residual penetration", "speed_in"}};
constexpr SignatureTrend kHysteresis[] = {{"residual vy", "abs_vin_y"},
                                          {"param restitution", "abs_vin_y"}};
constexpr SignatureTrend kDepthTangential[] = {{"residual vx", "penetration"}};
constexpr SignatureTrend kSlidingDrag[] = {{"residual vx", "vin_x"}};
constexpr SignatureTrend kRolling[] = {{"residual w", "win"}};

std::span<const SignatureTrend> trends_of(const ForceTerm& t) {
  if (t.elastic) return kElastic;
  switch (t.kind.family) {
    case Family::kRestitution:
      return kHysteresis;
    case Family::kPloughing:
    case Family::kSlidingFriction:
      return kDepthTangential;
    case Family::kRollingResistance:
      return kRolling;
    default:
      break;
  }
  return t.component == ForceComponent::kNormal ? std::span<const SignatureTrend>(kNormalDrag)
                                                : std::span<const SignatureTrend>(kSlidingDrag);
}

class ForceTermEffect final : public Effect {
 public:
  explicit ForceTermEffect(const ForceTerm& term)
      : term_(term),
        name_(force_term_effect_name(term)),
        parameter_(force_term_parameter_name(term)),
        summary_(
            std::string(component_name(term.component)) + " force term " +
            std::string(term.expression) +
            (term.literature.empty() ? std::string() : " (" + std::string(term.literature) + ")")),
        equation_(std::string(term.component == ForceComponent::kNormal ? "fn = max(fn + "
                              : term.at_centre ? "fx_body (at the centre of mass) += "
                              : term.component == ForceComponent::kTangential ? "ft += "
                                                                              : "moment += ") +
                  std::string(term.expression) +
                  (term.component == ForceComponent::kNormal ? ", 0)" : "") +
                  ", c = " + parameter_),
        description_("coefficient c of " + std::string(term.expression) + " (0 = none)") {
    const double bound = force_term_bound(term);
    spec_[0] = {parameter_, term_.unit,  term.elastic ? -bound : 0.0, bound, 0.0, 0.0,
                true,       description_};
  }

  std::string_view name() const override { return name_; }
  std::string_view summary() const override { return summary_; }
  std::string_view equation() const override { return equation_; }
  std::string_view reference() const override {
    return term_.literature.empty() ? std::string_view(
                                          "the force-residual discovery's library (issue 33; "
                                          "docs/diagnosis.md)")
                                    : term_.literature;
  }
  Stage stage() const override {
    switch (term_.component) {
      case ForceComponent::kNormal:
        return Stage::kNormal;
      case ForceComponent::kTangential:
        return term_.at_centre ? Stage::kBody : Stage::kTangential;
      case ForceComponent::kMoment:
        break;
    }
    return Stage::kRolling;
  }
  LawKind kind() const override { return term_.kind; }
  Signature signature() const override { return {summary_, trends_of(term_)}; }
  bool generated() const override { return true; }
  bool default_candidate() const override { return false; }
  std::span<const ParameterSpec> parameters() const override { return spec_; }

  double max_added_stiffness(std::span<const double> values,
                             double max_penetration_m) const override {
    if (term_.stiffness == nullptr || values.empty()) return 0.0;
    return std::abs(values[0]) * term_.stiffness(max_penetration_m);
  }

  // Scalar lanes: a term is one library function for every lane, called through a pointer (no
  // vectorisation); the terms are opt-in and a contact has one or two slots.
  void apply(const ContactBatch& c, const double* const* p, double* const*) const override {
    const double* coef = p[0];
    double* out = term_.component == ForceComponent::kNormal       ? c.fn
                  : term_.at_centre                                ? c.fx_body
                  : term_.component == ForceComponent::kTangential ? c.ft
                                                                   : c.moment;
    for (std::size_t i = 0; i < c.n; ++i) {
      if (!(c.active[i] > 0.0)) continue;
      const ContactSample s{.h_m = c.h[i],
                            .vn_mps = c.vn[i],
                            .vt_mps = c.vt[i],
                            .vx_mps = c.vx[i],
                            .omega_radps = c.w[i],
                            .loading = c.dh[i] > 0.0};
      const double add = coef[i] * term_.value(s);
      out[i] =
          term_.component == ForceComponent::kNormal ? std::max(out[i] + add, 0.0) : out[i] + add;
    }
  }

 private:
  const ForceTerm& term_;
  std::string name_, parameter_, summary_, equation_, description_;
  ParameterSpec spec_[1];
};

}  // namespace

std::string_view component_name(ForceComponent c) {
  switch (c) {
    case ForceComponent::kNormal:
      return "normal";
    case ForceComponent::kTangential:
      return "tangential";
    case ForceComponent::kMoment:
      return "moment";
  }
  return "?";
}

const std::vector<ForceTerm>& force_terms() {
  using C = ForceComponent;
  using F = Family;
  using V = Variable;
  static const std::vector<ForceTerm> terms = {
      {"spring",
       C::kNormal,
       "c h",
       "N/m",
       "linear spring (Katsuragi-Durian k z)",
       {F::kStiffness, V::kPenetration},
       true,
       [](const ContactSample& s) { return s.h_m; },
       [](double) { return 1.0; }},
      {"hertz",
       C::kNormal,
       "c h^1.5",
       "N/m^1.5",
       "Hertz contact",
       {F::kStiffness, V::kPenetration},
       true,
       [](const ContactSample& s) { return std::pow(s.h_m, 1.5); },
       [](double h) { return 1.5 * std::sqrt(h); }},
      {"quadratic_depth",
       C::kNormal,
       "c h^2",
       "N/m^2",
       "",
       {F::kStiffness, V::kPenetration},
       true,
       [](const ContactSample& s) { return s.h_m * s.h_m; },
       [](double h) { return 2.0 * h; }},
      {"inertial_drag",
       C::kNormal,
       "-c v_n|v_n|",
       "kg/m",
       "Poncelet / Katsuragi-Durian inertial drag (c = m/d1)",
       {F::kDrag, V::kNormalSpeed},
       false,
       [](const ContactSample& s) { return -s.vn_mps * std::abs(s.vn_mps); }},
      {"viscous",
       C::kNormal,
       "-c v_n",
       "N s/m",
       "viscous damping",
       {F::kDrag, V::kNormalSpeed},
       false,
       [](const ContactSample& s) { return -s.vn_mps; }},
      {"depth_drag",
       C::kNormal,
       "-c h v_n|v_n|",
       "kg/m^2",
       "",
       {F::kDrag, V::kNormalSpeed},
       false,
       [](const ContactSample& s) { return -s.h_m * s.vn_mps * std::abs(s.vn_mps); }},
      // One branch term, not one per branch: h on loading plus h on unloading is h itself,
      // and a library with both and the spring would be singular.
      {"branch_spring",
       C::kNormal,
       "c h sign(-v_n)",
       "N/m",
       "hysteresis: stiffer loading than unloading (Walton & Braun 1986)",
       {F::kRestitution, V::kPenetration},
       false,
       [](const ContactSample& s) { return s.loading ? s.h_m : -s.h_m; },
       [](double) { return 1.0; }},
      {"ploughing",
       C::kTangential,
       "-c sign(v_x) h^2",
       "N/m^2",
       "Rankine passive earth pressure (c = K_p gamma L / 2)",
       {F::kPloughing, V::kPenetration},
       false,
       [](const ContactSample& s) { return -sgn(s.vx_mps) * s.h_m * s.h_m; },
       nullptr,
       true},
      {"depth_friction_force",
       C::kTangential,
       "-c sign(v_t) h",
       "N/m",
       "",
       {F::kSlidingFriction, V::kPenetration},
       false,
       [](const ContactSample& s) { return -sgn(s.vt_mps) * s.h_m; }},
      {"tangential_viscous",
       C::kTangential,
       "-c v_t",
       "N s/m",
       "viscous damping",
       {F::kDrag, V::kSlipSpeed},
       false,
       [](const ContactSample& s) { return -s.vt_mps; }},
      {"tangential_drag",
       C::kTangential,
       "-c v_t|v_t|",
       "kg/m",
       "inertial drag",
       {F::kDrag, V::kSlipSpeed},
       false,
       [](const ContactSample& s) { return -s.vt_mps * std::abs(s.vt_mps); }},
      {"depth_rolling",
       C::kMoment,
       "-c sign(omega) h",
       "N",
       "",
       {F::kRollingResistance, V::kPenetration},
       false,
       [](const ContactSample& s) { return -sgn(s.omega_radps) * s.h_m; }},
      {"rolling_viscous",
       C::kMoment,
       "-c omega",
       "N m s/rad",
       "viscous rolling damping",
       {F::kRollingResistance, V::kSpin},
       false,
       [](const ContactSample& s) { return -s.omega_radps; }},
  };
  return terms;
}

std::vector<const ForceTerm*> force_terms(ForceComponent c) {
  std::vector<const ForceTerm*> out;
  for (const ForceTerm& t : force_terms())
    if (t.component == c) out.push_back(&t);
  return out;
}

const ForceTerm* find_force_term(std::string_view name) {
  for (const ForceTerm& t : force_terms())
    if (t.name == name) return &t;
  return nullptr;
}

std::string force_term_effect_name(const ForceTerm& term) {
  return "term_" + std::string(term.name);
}

std::string force_term_parameter_name(const ForceTerm& term) {
  return "c_" + std::string(term.name);
}

double force_term_bound(const ForceTerm& term) {
  const double ref = term.component == ForceComponent::kMoment ? kMomentRef_Nm : kForceRef_N;
  return ref / std::abs(term.value(kReference));
}

std::unique_ptr<Effect> make_force_term(const ForceTerm& term) {
  return std::make_unique<ForceTermEffect>(term);
}

std::vector<std::unique_ptr<Effect>> make_force_term_effects() {
  std::vector<std::unique_ptr<Effect>> out;
  for (const ForceTerm& t : force_terms()) out.push_back(make_force_term(t));
  return out;
}

std::string force_term_family_text() {
  std::string names;
  for (const ForceTerm& t : force_terms())
    names += (names.empty() ? "" : ", ") + std::string(t.name);
  return "force terms term_<name> with name in {" + names + "}";
}

}  // namespace ricochet::effects
