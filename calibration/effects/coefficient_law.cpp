// `<coefficient>_<variable>_<form>`: the generated coefficient laws (coefficient_law.hpp).
#include "effects/coefficient_law.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

// glibc's libmvec has vector pow and atan2 (x86-64 vector ABI, <= 4 ulp; pow(x, 0) = 1 exactly,
// so the neutral law stays bit for bit the paper's); <math.h> declares them only under
// -ffast-math. Declaring them lets the lane loops of the power and incidence-angle laws
// vectorise: scalar pow calls were a fifth of the lab-triangle diagnosis (issue 13).
extern "C" {
#pragma omp declare simd notinbranch
double pow(double, double) noexcept;
#pragma omp declare simd notinbranch
double atan2(double, double) noexcept;
}

namespace ricochet::effects {
namespace {

enum class Coef { kKn, kEn2, kMu, kMuR };
enum class Var { kApproach, kSlip, kSpin, kPenetration, kIncidence };
enum class Form { kLinear, kPower };
/// What a law does to the elastic curve: nothing (en2, mu, muR), the loading factor (kn in a
/// variable other than h), or the integral of the loading factor (kn in h).
enum class Elastic { kNone, kSame, kIntegral };

constexpr std::array<std::string_view, 4> kCoefNames = {"kn", "en2", "mu", "muR"};
constexpr std::array<std::string_view, 5> kVarNames = {"approach_speed", "slip_speed", "spin",
                                                       "penetration", "incidence_angle"};
constexpr std::array<std::string_view, 2> kFormNames = {"linear", "power"};
constexpr std::array<std::string_view, 4> kCoefSymbols = {"k_n", "e_n^2", "mu", "mu_R"};
// The role of the paper's parameter that each coefficient multiplies: a signature trend names the
// base model's calibrated parameter by it ("param restitution").
constexpr std::array<ParameterRole, 4> kCoefRoles = {
    ParameterRole::kNormalStiffness, ParameterRole::kRestitution, ParameterRole::kFrictionCap,
    ParameterRole::kRollingCap};

// The factor's range, and the floor of x in the power form relative to x_ref.
constexpr double kFactorMin = 0.02, kFactorMax = 50.0, kFloor = 1e-3;

constexpr std::array<LawVariable, 5> kVars = {{
    {"approach_speed", "vapp", "m/s", "v0",
     "largest approach speed -v_n of the contact so far (held)", 2.5, 6.0},
    {"slip_speed", "slip", "m/s", "|v_t|", "sliding speed |v_t| of the contact point", 1.0, 5.0},
    {"spin", "spin", "rad/s", "|omega|", "spin |omega| of the block", 40.0, 100.0},
    // 3 mm: the overlap scale of the paper's kn = 1e7 N/m at lab speeds.
    {"penetration", "h", "m", "h", "penetration (overlap) h of the contact", 3e-3, 1e-2},
    {"incidence_angle", "theta", "rad", "theta_in",
     "angle of the centre velocity below the horizontal at contact onset, atan2(-v_y, |v_x|) "
     "(held)",
     0.7, 1.5},
}};

struct VarText {
  std::string_view inverse_unit;  // unit of the linear slope c
  std::string_view words;         // in summaries and meanings
  std::string_view feature;       // impact feature of its signature (diagnosis/trends.hpp)
};
constexpr std::array<VarText, 5> kVarText = {{
    {"s/m", "the approach speed", "abs_vin_y"},
    {"s/m", "the slip speed", "vin_x"},
    {"s/rad", "the spin |omega|", "win"},
    {"1/m", "the penetration", "penetration"},
    {"1/rad", "the incidence angle", "impact_angle"},
}};

constexpr std::string_view kDiscrepancyRef =
    "Brynjarsdottir & O'Hagan (2014) Inverse Problems 30, 114007 (a parameter that drifts with "
    "a feature absorbs missing physics)";

// The physics family a law generalises, where the literature or the catalog has one.
std::string_view family_reference(Coef c, Var v) {
  if (c == Coef::kEn2 && v == Var::kApproach)
    return "Bourrier et al. (2009) Geomorphology 107: restitution falling with impact speed "
           "(catalog rate_restitution)";
  if (c == Coef::kEn2 && v == Var::kIncidence)
    return "Asteriou, Saroglou & Tsiambaos (2012) Int. J. Rock Mech. Min. Sci. 54: restitution "
           "against the impact angle";
  if (c == Coef::kMu && v == Var::kPenetration)
    return "Lu et al. (2019) Landslides 16: RAMMS::ROCKFALL scarring, friction growing with "
           "penetration (catalog depth_friction)";
  if (c == Coef::kMu && v == Var::kSlip)
    return "Dieterich (1979) J. Geophys. Res. 84: rate-dependent friction";
  if (c == Coef::kMuR && v == Var::kSpin)
    return "Ai, Chen, Rotter & Ooi (2011) Powder Technol. 206: rolling resistance with a "
           "spin-rate (viscous) part";
  if (c == Coef::kKn && v == Var::kPenetration)
    return "Johnson (1985) Contact Mechanics: stiffness growing with indentation, Hertz "
           "k ~ h^(1/2) (catalog hertz_stiffness)";
  return {};
}

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

inline double clamp_factor(double f) {
  return f < kFactorMin ? kFactorMin : (f > kFactorMax ? kFactorMax : f);
}

// Stiffness laws in h: Psi(h) = integral_0^h g(s) ds of the loading factor g actually applied
// (floor and clamp included), so that Phi(h) = kn Psi(h) is the elastic curve of direct
// unloading, and the loading factor over a step is the secant (Psi(h) - Psi(h - dh)) / dh: the
// incremental force then sums to exactly kn Psi(h) on loading, and a closed cycle returns e_n^2
// of the stored energy (paper Eq. 4) however fast g varies within a step.
//
// Linear, g(s) = clamp(1 + c s): s (1 + c s / 2) until g reaches its clamp at s_c, then linear.
inline double psi_linear(double c, double s) {
  const double sc = c > 0.0 ? (kFactorMax - 1.0) / c : (c < 0.0 ? (kFactorMin - 1.0) / c : 1e300);
  const double fc = c > 0.0 ? kFactorMax : kFactorMin;
  return s > sc ? sc * (1.0 + 0.5 * c * sc) + fc * (s - sc) : s * (1.0 + 0.5 * c * s);
}

// Power, g(s) = clamp((max(s, h_min) / h_ref)^p): constant f1 below h1 (the floor h_min or the
// clamp), the power law between h1 and h2, constant f2 above h2 (the other clamp):
//   Psi(s) = f1 s                                        for s <= h1,
//          = h1 f1 (1 + E) + f2 max(s - h2, 0)           above,
//   E = expm1(q L) / q,  q = 1 + p,  L = ln(min(s, h2) / h1)   (E = L at p = -1).
// h1, h2, f1 depend on p only: computed once per lane and step, then Psi at h and h - dh.
// (Not for p = 0, where the caller keeps g = 1.)
struct PowerIntegral {
  double h1, h2, f1, f2, q;
  PowerIntegral(double p, double h_ref) {
    // (c)^(1/p) = exp(ln c / p): where the power law meets the clamps.
    const double ln_lo = std::log(p > 0.0 ? kFactorMin : kFactorMax);
    const double ln_hi = std::log(p > 0.0 ? kFactorMax : kFactorMin);
    const double s_lo = h_ref * std::exp(ln_lo / p);
    const double h_min = kFloor * h_ref;
    const bool clamped_low = s_lo > h_min;
    h1 = clamped_low ? s_lo : h_min;
    h2 = h_ref * std::exp(ln_hi / p);
    f1 = clamped_low ? (p > 0.0 ? kFactorMin : kFactorMax)
                     : clamp_factor(std::exp(p * std::log(kFloor)));
    f2 = p > 0.0 ? kFactorMax : kFactorMin;
    q = 1.0 + p;
  }
  double operator()(double s) const {
    const double ss = s > h1 ? (s < h2 ? s : h2) : h1;
    const double l = std::log(ss / h1);
    const double e = q != 0.0 ? std::expm1(q * l) / q : l;
    const double beyond = s > h2 ? s - h2 : 0.0;
    return s > h1 ? h1 * f1 * (1.0 + e) + f2 * beyond : f1 * s;
  }
};

using RunFn = void (*)(const ContactBatch&, const double*, double*, double*);

// One lane loop per (variable, form, elastic handling): all known at compile time, so the loop
// is branch-free and vectorises (effect.hpp). `held`: the law's state (approach speed or onset
// angle), null for the variables read live.
template <Var V, Form F, Elastic K>
void run(const ContactBatch& cb, const double* __restrict a, double* __restrict held,
         double* __restrict factor) {
  constexpr double x_ref = kVars[static_cast<int>(V)].x_ref;
  constexpr double x_min = kFloor * x_ref;
  const double* __restrict active = cb.active;
  double* __restrict elastic = cb.elastic_factor;
  const std::size_t n = cb.n;
  RICOCHET_SIMD
  for (std::size_t i = 0; i < n; ++i) {
    double x;
    if constexpr (V == Var::kApproach) {
      x = hold_max_approach(held[i], cb.vn[i], active[i]);
    } else if constexpr (V == Var::kSlip) {
      x = std::fabs(cb.vt[i]);
    } else if constexpr (V == Var::kSpin) {
      x = std::fabs(cb.w[i]);
    } else if constexpr (V == Var::kPenetration) {
      x = cb.h[i];
    } else {  // incidence angle at contact onset (the state is 0 until the first contact step)
      const double theta = ::atan2(-cb.vy[i], std::fabs(cb.vx[i]));
      const double kept = held[i] != 0.0 ? held[i] : theta;
      held[i] = active[i] > 0.0 ? kept : 0.0;
      x = held[i];
    }
    if constexpr (K == Elastic::kIntegral) {
      // x = h; `held` = Psi at the previous step's h (0 at contact onset, as h is), so the
      // secant over the step telescopes: the loading force is exactly kn Psi(h). The neutral
      // a = 0 leaves both factors untouched (bit for bit the paper's law); a step too small for
      // a secant (its force increment kn f dh vanishes with it) takes the mean Psi(h) / h.
      double psi_h;
      if constexpr (F == Form::kLinear)
        psi_h = a[i] != 0.0 ? psi_linear(a[i], x) : x;
      else
        psi_h = a[i] != 0.0 ? PowerIntegral(a[i], x_ref)(x) : x;
      const double mean = x > 0.0 ? psi_h / x : 1.0;
      const double secant = step_secant(held[i], psi_h, cb.dh[i], x, active[i], mean);
      factor[i] *= a[i] != 0.0 ? secant : 1.0;
      elastic[i] *= a[i] != 0.0 ? mean : 1.0;
    } else {
      double f;
      if constexpr (F == Form::kLinear)
        f = clamp_factor(1.0 + a[i] * x);
      else
        f = clamp_factor(::pow((x > x_min ? x : x_min) / x_ref, a[i]));
      factor[i] *= f;
      if constexpr (K == Elastic::kSame) elastic[i] *= f;
    }
  }
}

template <Var V, Form F>
RunFn pick(Elastic k) {
  if constexpr (V == Var::kPenetration)
    if (k == Elastic::kIntegral) return &run<V, F, Elastic::kIntegral>;
  return k == Elastic::kSame ? &run<V, F, Elastic::kSame> : &run<V, F, Elastic::kNone>;
}

template <Var V>
RunFn pick(Form f, Elastic k) {
  return f == Form::kLinear ? pick<V, Form::kLinear>(k) : pick<V, Form::kPower>(k);
}

RunFn pick(Var v, Form f, Elastic k) {
  switch (v) {
    case Var::kApproach:
      return pick<Var::kApproach>(f, k);
    case Var::kSlip:
      return pick<Var::kSlip>(f, k);
    case Var::kSpin:
      return pick<Var::kSpin>(f, k);
    case Var::kPenetration:
      return pick<Var::kPenetration>(f, k);
    case Var::kIncidence:
      return pick<Var::kIncidence>(f, k);
  }
  return nullptr;
}

class CoefficientLaw final : public Effect {
 public:
  CoefficientLaw(Coef c, Var v, Form f) : coef_(c), var_(v), form_(f) {
    const LawVariable& vi = kVars[static_cast<int>(v)];
    const VarText& vt = kVarText[static_cast<int>(v)];
    const std::string cn(kCoefNames[static_cast<int>(c)]);
    const std::string fn(kFormNames[static_cast<int>(f)]);
    const bool linear = f == Form::kLinear;
    name_ = coefficient_law_name(cn, vi.name, fn);
    param_name_ = std::string(linear ? "c_" : "p_") + cn + "_" + std::string(vi.tag);
    param_unit_ = linear ? std::string(vt.inverse_unit) : std::string("-");
    param_desc_ = linear ? "relative change of " + std::string(kCoefSymbols[static_cast<int>(c)]) +
                               " per unit of " + std::string(vi.symbol) + " (0 = constant)"
                         : "exponent of " + std::string(vi.symbol) + " (0 = constant)";
    spec_[0] = {param_name_,
                param_unit_,
                linear ? -0.9 / vi.x_hi : -1.5,
                linear ? 3.0 / vi.x_ref : 1.5,
                0.0,
                0.0,
                true,
                param_desc_};
    const std::string sym(kCoefSymbols[static_cast<int>(c)]);
    summary_ = sym + " as a " + fn + " function of " + std::string(vt.words) + " (generated law)";
    char ref[48];
    std::snprintf(ref, sizeof ref, "%g %s", vi.x_ref, std::string(vi.unit).c_str());
    const std::string x = std::string(vi.symbol);
    equation_ = linear ? sym + "_eff = " + sym + " * (1 + c * " + x + ")"
                       : sym + "_eff = " + sym + " * (max(" + x + ", 1e-3 x_ref) / " + ref + ")^p";
    if (c == Coef::kKn && v == Var::kPenetration)
      equation_ +=
          "; elastic curve Phi(h) = k_n * integral_0^h of the clamped factor (" +
          std::string(linear ? "h (1 + c h / 2) below the clamp"
                             : "about h (h / x_ref)^p / (1 + p) well above the floor") +
          "), loading factor its secant over the step (state psi: Psi(h) of the previous step)";
    equation_ += "; factor clamped to [0.02, 50]";
    reference_ = std::string(kDiscrepancyRef);
    if (const auto family = family_reference(c, v); !family.empty())
      reference_ += "; generalises " + std::string(family);
    meaning_ =
        sym + " grows or falls with " + std::string(vt.words) + " (generated " + fn + " law)";
    state_[0] = v == Var::kIncidence  ? StateSpec{"theta_in", "rad"}
                : v == Var::kApproach ? StateSpec{"v0", "m/s"}
                                      : StateSpec{"psi", "m"};  // kn in h
    // Signature: the calibrated coefficient drifts with the matching feature, and the residuals
    // the coefficient drives.
    const std::string feature(vt.feature);
    const std::string param = "param " + std::string(role_name(kCoefRoles[static_cast<int>(c)]));
    trends_.push_back({param, feature});
    if (v == Var::kApproach) trends_.push_back({param, "speed_in"});
    if (c == Coef::kEn2) trends_.push_back({"residual vy", feature});
    if (c == Coef::kMu || c == Coef::kMuR) {
      trends_.push_back({"residual vx", feature});
      trends_.push_back({"residual w", feature});
    }
    if (c == Coef::kKn) {
      trends_.push_back({"residual penetration", feature});
      trends_.push_back({"residual contact_duration", feature});
    }
    for (const auto& [q, f2] : trends_) sig_.push_back({q, f2});
    const Elastic k = c != Coef::kKn           ? Elastic::kNone
                      : v == Var::kPenetration ? Elastic::kIntegral
                                               : Elastic::kSame;
    run_ = pick(v, f, k);
  }

  std::string_view name() const override { return name_; }
  std::string_view summary() const override { return summary_; }
  std::string_view equation() const override { return equation_; }
  std::string_view reference() const override { return reference_; }
  Stage stage() const override { return Stage::kCoefficient; }
  LawKind kind() const override {
    static constexpr std::array<Family, 4> kFamilies = {Family::kStiffness, Family::kRestitution,
                                                        Family::kSlidingFriction,
                                                        Family::kRollingResistance};
    static constexpr std::array<Variable, 5> kVariables = {
        Variable::kImpactSpeed, Variable::kSlipSpeed, Variable::kSpin, Variable::kPenetration,
        Variable::kIncidenceAngle};
    return {kFamilies[static_cast<std::size_t>(coef_)], kVariables[static_cast<std::size_t>(var_)]};
  }
  std::span<const ParameterSpec> parameters() const override { return spec_; }
  std::span<const StateSpec> state() const override {
    return holds_state() ? std::span<const StateSpec>(state_) : std::span<const StateSpec>();
  }
  Signature signature() const override { return {meaning_, sig_, coef_ == Coef::kKn}; }
  bool generated() const override { return true; }
  // A stiffness law's factor (its secant, for a law in h) stays within the clamp; a linear law
  // with c <= 0 never raises it, nor does any law at its neutral 0.
  double max_stiffness_factor(std::span<const double> v, double) const override {
    if (coef_ != Coef::kKn || v.empty() || v[0] == 0.0) return 1.0;
    return form_ == Form::kLinear && v[0] < 0.0 ? 1.0 : kFactorMax;
  }

  std::string law(std::span<const double> values) const override {
    const LawVariable& vi = kVars[static_cast<int>(var_)];
    const std::string sym(kCoefSymbols[static_cast<int>(coef_)]);
    const std::string base = coef_ == Coef::kEn2 ? "e_n0^2" : sym + "0";
    char buf[256];
    const double x = values.empty() ? 0.0 : values[0];
    if (form_ == Form::kLinear)
      std::snprintf(buf, sizeof buf, "%s = %s (1 + c %s), c = %.4g %s", sym.c_str(), base.c_str(),
                    std::string(vi.symbol).c_str(), x,
                    std::string(kVarText[static_cast<int>(var_)].inverse_unit).c_str());
    else
      std::snprintf(buf, sizeof buf, "%s = %s (%s / %g %s)^p, p = %.4g", sym.c_str(), base.c_str(),
                    std::string(vi.symbol).c_str(), vi.x_ref, std::string(vi.unit).c_str(), x);
    return buf;
  }

  void apply(const ContactBatch& cb, const double* const* p, double* const* s) const override {
    double* factor = coef_ == Coef::kKn    ? cb.kn_factor
                     : coef_ == Coef::kEn2 ? cb.en2_factor
                     : coef_ == Coef::kMu  ? cb.mu_factor
                                           : cb.muR_factor;
    run_(cb, p[0], holds_state() ? s[0] : nullptr, factor);
  }

 private:
  // The approach speed and the onset angle are held over the contact; a stiffness law in h holds
  // Psi(h) of the previous step (integral of its loading factor).
  bool holds_state() const {
    return var_ == Var::kApproach || var_ == Var::kIncidence ||
           (coef_ == Coef::kKn && var_ == Var::kPenetration);
  }

  Coef coef_;
  Var var_;
  Form form_;
  RunFn run_ = nullptr;
  std::string name_, param_name_, param_unit_, param_desc_, summary_, equation_, reference_,
      meaning_;
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
std::span<const LawVariable> law_variable_info() {
  return kVars;
}

std::string coefficient_law_name(std::string_view coefficient, std::string_view variable,
                                 std::string_view form) {
  return std::string(coefficient) + "_" + std::string(variable) + "_" + std::string(form);
}

std::string coefficient_law_parameter_name(std::string_view coefficient, std::string_view variable,
                                           std::string_view form) {
  find_or_throw(kCoefNames, coefficient, "coefficient");
  const auto v = find_or_throw(kVarNames, variable, "variable");
  const auto f = find_or_throw(kFormNames, form, "form");
  return std::string(f == 0 ? "c_" : "p_") + std::string(coefficient) + "_" +
         std::string(kVars[v].tag);
}

std::optional<CoefficientLawConfig> parse_coefficient_law_name(std::string_view effect_name) {
  for (auto c : kCoefNames)
    for (auto v : kVarNames)
      for (auto f : kFormNames)
        if (effect_name == coefficient_law_name(c, v, f)) return CoefficientLawConfig{c, v, f};
  return std::nullopt;
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
