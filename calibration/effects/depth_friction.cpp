// `depth_friction`: friction that hardens with penetration depth, a depth form of the soil
// hardening / scarring laws of rockfall codes (RAMMS::ROCKFALL scarring; Lu et al. 2019):
//   mu_eff = mu * (1 + a_mu * h).
// Signature: per-release calibrated mu trends with penetration depth.
#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"a_mu", "1/m", 0.0, 2000.0, 0.0, 0.0, true, "friction hardening per metre of penetration"},
};

// Signature: the residual and parameter trends of this family (docs/effects/depth_friction.md,
// "Signature in residuals", which gives the physical reasoning and the literature).
constexpr SignatureTrend kSignature[] = {
    {"param friction_cap", "penetration"},
    {"residual vx", "penetration"},
    {"residual w", "penetration"},
};

class DepthFriction final : public Effect {
 public:
  std::string_view name() const override { return "depth_friction"; }
  std::string_view summary() const override {
    return "friction coefficient grows linearly with penetration";
  }
  std::string_view equation() const override { return "mu_eff = mu * (1 + a_mu * h)"; }
  std::string_view reference() const override {
    return "Lu, Caviezel, Christen et al. (2019) Landslides 16 (RAMMS::ROCKFALL scarring)";
  }
  Stage stage() const override { return Stage::kCoefficient; }
  LawKind kind() const override { return {Family::kSlidingFriction, Variable::kPenetration}; }
  Signature signature() const override {
    return {"friction hardening with penetration depth", kSignature};
  }
  std::span<const ParameterSpec> parameters() const override { return kParams; }

  void apply(const ContactBatch& c, const double* const* p, double* const*) const override {
    const double* __restrict a = p[0];
    const double* __restrict h = c.h;
    double* __restrict muf = c.mu_factor;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) muf[i] *= 1.0 + a[i] * h[i];
  }
};

}  // namespace

std::unique_ptr<Effect> make_depth_friction() {
  return std::make_unique<DepthFriction>();
}

}  // namespace ricochet::effects
