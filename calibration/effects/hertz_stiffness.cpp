// `hertz_stiffness`: penetration-dependent normal stiffness. Bearing capacity grows with depth;
// a Hertz-like contact has k ~ sqrt(h). Blended with the paper's linear law by beta:
//   kn_eff(h) = kn * ((1 - beta) + beta * sqrt(h / h_ref)),
// and the elastic curve used for direct unloading is its integral,
//   Phi(h) = kn h ((1 - beta) + (2/3) beta sqrt(h / h_ref)),
// so a full cycle still returns exactly e_n^2 of the stored energy (Eq. 4 holds for any beta).
// Signature: contact duration and penetration change, rebound velocities barely.
#include <algorithm>
#include <cmath>
#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"beta", "-", 0.0, 1.0, 0.0, 0.0, true, "weight of the Hertz-like sqrt(h) stiffness"},
    {"h_ref", "m", 1e-4, 0.05, 2e-3, NAN, false, "penetration at which kn_eff = kn",
     ParameterRole::kOther, IdentifiedBy::kNothing},
};

// Signature: the residual and parameter trends of this family (docs/effects/hertz_stiffness.md,
// "Signature in residuals", which gives the physical reasoning and the literature).
constexpr SignatureTrend kSignature[] = {
    {"residual contact_duration", "speed_in"},
    {"residual penetration", "speed_in"},
    {"residual contact_duration", "abs_vin_y"},
};

class HertzStiffness final : public Effect {
 public:
  std::string_view name() const override { return "hertz_stiffness"; }
  std::string_view summary() const override {
    return "normal stiffness grows as sqrt(penetration) (Hertz-like bearing)";
  }
  std::string_view equation() const override {
    return "kf *= (1-beta) + beta*sqrt(h/h_ref);  ke *= (1-beta) + (2/3)*beta*sqrt(h/h_ref)";
  }
  std::string_view reference() const override {
    return "Hertz contact, k ~ sqrt(h) (Johnson 1985, Contact Mechanics); Thornton & Ning (1998)";
  }
  Stage stage() const override { return Stage::kCoefficient; }
  LawKind kind() const override { return {Family::kStiffness, Variable::kPenetration}; }
  Signature signature() const override {
    return {"a normal stiffness growing with penetration (Hertz-like bearing)", kSignature, true};
  }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  // The loading factor grows without bound with sqrt(h / h_ref): at the deepest penetration
  // the engine's stable step must still hold (critical_time_step).
  double max_stiffness_factor(std::span<const double> v, double max_penetration_m) const override {
    const double beta = v[0], h_ref = v[1];
    const double r = std::sqrt(max_penetration_m / h_ref);
    return std::max(1.0, (1.0 - beta) + beta * r);
  }

  void apply(const ContactBatch& c, const double* const* p, double* const*) const override {
    const double* __restrict beta = p[0];
    const double* __restrict href = p[1];
    const double* __restrict h = c.h;
    double* __restrict kf = c.kn_factor;
    double* __restrict ef = c.elastic_factor;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      const double r = std::sqrt(h[i] / href[i]);
      kf[i] *= (1.0 - beta[i]) + beta[i] * r;
      ef[i] *= (1.0 - beta[i]) + (2.0 / 3.0) * beta[i] * r;
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_hertz_stiffness() {
  return std::make_unique<HertzStiffness>();
}

}  // namespace ricochet::effects
