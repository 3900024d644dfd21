// `<coefficient>_<variable>_<form>`: the generated coefficient laws (coefficient_law.hpp).
#include "effects/coefficient_law.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ricochet::effects {
namespace {

enum class Coef { kKn, kEn2, kMu, kMuR };
enum class Var { kApproach, kSlip, kSpin, kPenetration, kIncidence };
enum class Form { kLinear, kPower };

constexpr std::array<std::string_view, 4> kCoefNames = {"kn", "en2", "mu", "muR"};
constexpr std::array<std::string_view, 5> kVarNames = {"approach_speed", "slip_speed", "spin",
                                                       "penetration", "incidence_angle"};
constexpr std::array<std::string_view, 2> kFormNames = {"linear", "power"};

struct VarInfo {
  std::string_view short_name;  // in parameter names
  std::string_view unit, inverse_unit;
  double x_ref, x_hi;
  std::string_view symbol;   // in printed laws
  std::string_view words;    // in meanings
  std::string_view feature;  // impact feature of its signature (diagnosis/trends.hpp)
};
constexpr std::array<VarInfo, 5> kVars = {{
    {"vapp", "m/s", "s/m", 2.5, 6.0, "v0", "the approach speed", "abs_vin_y"},
    {"slip", "m/s", "s/m", 1.0, 5.0, "|v_t|", "the slip speed", "vin_x"},
    {"spin", "rad/s", "s/rad", 40.0, 100.0, "|omega|", "the spin |omega|", "win"},
    {"h", "m", "1/m", 3e-3, 1e-2, "h", "the penetration", "penetration"},
    {"theta", "rad", "1/rad", 0.7, 1.5, "theta_in", "the incidence angle", "impact_angle"},
}};
constexpr std::array<std::string_view, 4> kCoefSymbols = {"k_n", "e_n^2", "mu", "mu_R"};

std::string list(std::span<const std::string_view> names) {
  std::string s;
  for (auto n : names) s += (s.empty() ? "" : ", ") + std::string(n);
  return s;
}

template <std::size_t N>
std::size_t find_or_throw(const std::array<std::string_view, N>& names, std::string_view value,
                          const char* what) {
  for (std::size_t i = 0; i < N; ++i)
    if (names[i] == value) return i;
  throw std::invalid_argument("unknown coefficient-law " + std::string(what) + " '" +
                              std::string(value) + "'; accepted: " + list(names));
}

class CoefficientLaw final : public Effect {
 public:
  CoefficientLaw(Coef c, Var v, Form f) : coef_(c), var_(v), form_(f) {
    const VarInfo& vi = kVars[static_cast<int>(v)];
    const std::string cn(kCoefNames[static_cast<int>(c)]);
    name_ =
        coefficient_law_name(cn, kVarNames[static_cast<int>(v)], kFormNames[static_cast<int>(f)]);
    param_name_ =
        std::string(f == Form::kLinear ? "c_" : "p_") + cn + "_" + std::string(vi.short_name);
    param_unit_ = f == Form::kLinear ? std::string(vi.inverse_unit) : std::string("-");
    const double lo = f == Form::kLinear ? -0.9 / vi.x_hi : -1.5;
    const double hi = f == Form::kLinear ? 3.0 / vi.x_ref : 1.5;
    param_desc_ = f == Form::kLinear ? "slope of the relative change per unit of the variable"
                                     : "exponent of the power law (0 = constant)";
    spec_[0] = {param_name_, param_unit_, lo, hi, 0.0, 0.0, true, param_desc_};
    const std::string sym(kCoefSymbols[static_cast<int>(c)]);
    summary_ = sym + " as a " + std::string(kFormNames[static_cast<int>(f)]) + " function of " +
               std::string(vi.words) + " (generated law)";
    char ref[32];
    std::snprintf(ref, sizeof ref, "%g %s", vi.x_ref, std::string(vi.unit).c_str());
    equation_ = f == Form::kLinear
                    ? sym + "_eff = " + sym + " * (1 + c * " + std::string(vi.symbol) + ")"
                    : sym + "_eff = " + sym + " * (" + std::string(vi.symbol) + " / " + ref + ")^p";
    if (c == Coef::kKn && v == Var::kPenetration)
      equation_ += f == Form::kLinear ? "; elastic curve Phi = k_n h (1 + c h / 2)"
                                      : "; elastic curve Phi = k_n h (h / x_ref)^p / (1 + p)";
    equation_ += "; factor clamped to [0.02, 50]";
    meaning_ = sym + " grows or falls with " + std::string(vi.words) + " (generated " +
               std::string(kFormNames[static_cast<int>(f)]) + " law)";
    state_[0] = {v == Var::kIncidence ? "theta_in" : "v0", v == Var::kIncidence ? "rad" : "m/s"};
    // Signature: the calibrated coefficient drifts with the matching feature, and the residuals
    // the coefficient drives.
    trends_.push_back({"param " + cn, std::string(vi.feature)});
    if (v == Var::kApproach) trends_.push_back({"param " + cn, "speed_in"});
    if (c == Coef::kEn2) trends_.push_back({"residual vy", std::string(vi.feature)});
    if (c == Coef::kMu || c == Coef::kMuR) {
      trends_.push_back({"residual vx", std::string(vi.feature)});
      trends_.push_back({"residual w", std::string(vi.feature)});
    }
    if (c == Coef::kKn) {
      trends_.push_back({"residual penetration", std::string(vi.feature)});
      trends_.push_back({"residual contact_duration", std::string(vi.feature)});
    }
    for (const auto& [q, f2] : trends_) sig_.push_back({q, f2});
  }

  std::string_view name() const override { return name_; }
  std::string_view summary() const override { return summary_; }
  std::string_view equation() const override { return equation_; }
  std::string_view reference() const override {
    return "Brynjarsdottir & O'Hagan (2014) Inverse Problems 30, 114007 (parameters that drift "
           "with a feature absorb missing physics); forms as in Bourrier et al. (2009) "
           "Geomorphology 107 (restitution vs speed) and Lu et al. (2019) Landslides 16 "
           "(friction vs penetration)";
  }
  Stage stage() const override { return Stage::kCoefficient; }
  std::span<const ParameterSpec> parameters() const override { return spec_; }
  std::span<const StateSpec> state() const override {
    // Approach speed and incidence angle are held over the contact; the others are read live.
    return var_ == Var::kApproach || var_ == Var::kIncidence ? std::span<const StateSpec>(state_)
                                                             : std::span<const StateSpec>();
  }
  Signature signature() const override { return {meaning_, sig_, coef_ == Coef::kKn, true}; }

  std::string law(std::span<const double> values) const override {
    const VarInfo& vi = kVars[static_cast<int>(var_)];
    const std::string sym(kCoefSymbols[static_cast<int>(coef_)]);
    const std::string base = coef_ == Coef::kEn2 ? "e_n0^2" : sym + "0";
    char buf[256];
    const double x = values.empty() ? 0.0 : values[0];
    if (form_ == Form::kLinear)
      std::snprintf(buf, sizeof buf, "%s = %s (1 + c %s), c = %.4g %s", sym.c_str(), base.c_str(),
                    std::string(vi.symbol).c_str(), x, std::string(vi.inverse_unit).c_str());
    else
      std::snprintf(buf, sizeof buf, "%s = %s (%s / %g %s)^p, p = %.4g", sym.c_str(), base.c_str(),
                    std::string(vi.symbol).c_str(), vi.x_ref, std::string(vi.unit).c_str(), x);
    return buf;
  }

  void apply(const ContactBatch& cb, const double* const* p, double* const* s) const override {
    switch (var_) {
      case Var::kApproach:
        return run<Var::kApproach>(cb, p[0], s);
      case Var::kSlip:
        return run<Var::kSlip>(cb, p[0], s);
      case Var::kSpin:
        return run<Var::kSpin>(cb, p[0], s);
      case Var::kPenetration:
        return run<Var::kPenetration>(cb, p[0], s);
      case Var::kIncidence:
        return run<Var::kIncidence>(cb, p[0], s);
    }
  }

 private:
  // One lane loop per variable (the variable is known at compile time inside the loop, so it
  // vectorises; effect.hpp).
  template <Var V>
  void run(const ContactBatch& cb, const double* __restrict a, double* const* s) const {
    const VarInfo& vi = kVars[static_cast<int>(V)];
    const double* __restrict active = cb.active;
    double* __restrict factor = coef_ == Coef::kKn    ? cb.kn_factor
                                : coef_ == Coef::kEn2 ? cb.en2_factor
                                : coef_ == Coef::kMu  ? cb.mu_factor
                                                      : cb.muR_factor;
    double* __restrict elastic = cb.elastic_factor;
    const bool kn = coef_ == Coef::kKn;
    const bool kn_h = kn && V == Var::kPenetration;
    const bool linear = form_ == Form::kLinear;
    const double x_ref = vi.x_ref, x_min = 1e-3 * vi.x_ref;
    double* __restrict held = nullptr;
    if constexpr (V == Var::kApproach || V == Var::kIncidence) held = s[0];
    RICOCHET_SIMD
    for (std::size_t i = 0; i < cb.n; ++i) {
      double x;
      if constexpr (V == Var::kApproach) {
        const double v = held[i] > -cb.vn[i] ? held[i] : -cb.vn[i];
        held[i] = active[i] > 0.0 ? v : 0.0;
        x = held[i];
      } else if constexpr (V == Var::kSlip) {
        x = std::fabs(cb.vt[i]);
      } else if constexpr (V == Var::kSpin) {
        x = std::fabs(cb.w[i]);
      } else if constexpr (V == Var::kPenetration) {
        x = cb.h[i];
      } else {  // incidence angle at contact onset (the state is 0 until the first contact step)
        const double theta = std::atan2(-cb.vy[i], std::fabs(cb.vx[i]));
        const double kept = held[i] != 0.0 ? held[i] : theta;
        held[i] = active[i] > 0.0 ? kept : 0.0;
        x = held[i];
      }
      const double xs = (x > x_min ? x : x_min) / x_ref;
      double f = linear ? 1.0 + a[i] * x : std::pow(xs, a[i]);
      f = f < 0.02 ? 0.02 : (f > 50.0 ? 50.0 : f);
      // Elastic curve of a stiffness law in h: the integral of the loading stiffness.
      double e = f;
      if (kn_h) {
        e = linear ? 1.0 + 0.5 * a[i] * x : f / (1.0 + a[i]);
        e = e < 0.02 ? 0.02 : (e > 50.0 ? 50.0 : e);
      }
      factor[i] *= f;
      if (kn) elastic[i] *= e;
    }
  }

  Coef coef_;
  Var var_;
  Form form_;
  std::string name_, param_name_, param_unit_, param_desc_, summary_, equation_, meaning_;
  std::array<ParameterSpec, 1> spec_{};
  std::array<StateSpec, 1> state_{};
  std::vector<std::pair<std::string, std::string>> trends_;
  std::vector<SignatureTrend> sig_;
};

}  // namespace

std::span<const std::string_view> law_coefficients() {
  return kCoefNames;
}
std::span<const std::string_view> law_variables() {
  return kVarNames;
}
std::span<const std::string_view> law_forms() {
  return kFormNames;
}

std::string coefficient_law_name(std::string_view coefficient, std::string_view variable,
                                 std::string_view form) {
  return std::string(coefficient) + "_" + std::string(variable) + "_" + std::string(form);
}

std::unique_ptr<Effect> make_coefficient_law(std::string_view coefficient,
                                             std::string_view variable, std::string_view form) {
  const auto c = find_or_throw(kCoefNames, coefficient, "coefficient");
  const auto v = find_or_throw(kVarNames, variable, "variable");
  const auto f = find_or_throw(kFormNames, form, "form");
  return std::make_unique<CoefficientLaw>(static_cast<Coef>(c), static_cast<Var>(v),
                                          static_cast<Form>(f));
}

std::vector<std::unique_ptr<Effect>> make_coefficient_laws() {
  std::vector<std::unique_ptr<Effect>> out;
  for (auto c : kCoefNames)
    for (auto v : kVarNames)
      for (auto f : kFormNames) out.push_back(make_coefficient_law(c, v, f));
  return out;
}

std::string coefficient_law_family_text() {
  return "generated coefficient laws <coefficient>_<variable>_<form> with coefficient in {" +
         list(kCoefNames) + "}, variable in {" + list(kVarNames) + "}, form in {" +
         list(kFormNames) + "}";
}

}  // namespace ricochet::effects
