// `rate_restitution`: speed-dependent restitution. The energy restitution of a contact falls
// with its impact speed following Bourrier et al.'s rockfall-on-soil form for the velocity
// restitution, R(v) = v_half / (v_half + |v|) (PlatRock), written with kv = 1 / v_half so that
// kv = 0 recovers the paper's constant e_n^2:
//   e_n^2_eff = e_n^2 / (1 + kv * v0)^2,   v0 = largest approach speed of this contact so far.
// Signature in residuals: V_out^y residual and per-release e_n^2 trend with |V_in^y|.

#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"kv", "s/m", 0.0, 2.0, 0.0, 0.0, true,
     "inverse half-restitution speed 1/v_half (0 = speed-independent)"},
};
constexpr StateSpec kState[] = {{"v0", "m/s"}};

// Signature: the residual and parameter trends of this family (docs/effects/rate_restitution.md,
// "Signature in residuals", which gives the physical reasoning and the literature).
constexpr SignatureTrend kSignature[] = {
    {"residual vy", "abs_vin_y"},
    {"param restitution", "abs_vin_y"},
    {"param restitution", "speed_in"},
};

class RateRestitution final : public Effect {
 public:
  std::string_view name() const override { return "rate_restitution"; }
  std::string_view summary() const override {
    return "energy restitution falls with impact speed (Bourrier-type)";
  }
  std::string_view equation() const override {
    return "en2_eff = en2 / (1 + kv*v0)^2,  v0 = max approach speed -vn of the contact";
  }
  std::string_view reference() const override {
    return "Bourrier, Dorren, Nicot, Berger & Darve (2009) Geomorphology 107; PlatRock";
  }
  Stage stage() const override { return Stage::kCoefficient; }
  LawKind kind() const override { return {Family::kRestitution, Variable::kImpactSpeed}; }
  Signature signature() const override { return {"speed-dependent restitution", kSignature}; }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  std::span<const StateSpec> state() const override { return kState; }

  void apply(const ContactBatch& c, const double* const* p, double* const* s) const override {
    const double* __restrict kv = p[0];
    double* __restrict v0 = s[0];
    const double* __restrict vn = c.vn;
    const double* __restrict active = c.active;
    double* __restrict enf = c.en2_factor;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      const double r = 1.0 + kv[i] * hold_max_approach(v0[i], vn[i], active[i]);
      enf[i] /= r * r;
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_rate_restitution() {
  return std::make_unique<RateRestitution>();
}

}  // namespace ricochet::effects
