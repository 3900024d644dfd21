// `inertial_drag`: Poncelet inertial drag of the sand on a penetrating block. Katsuragi & Durian
// (2007) write m z'' = m g - k z - (m / d1) z'^2 for impacts into granular media; the last term
// is the speed-squared drag added here at each penetrating contact, with cd = m / d1:
//   fn += cd * vn^2   while the contact point moves into the ground (vn < 0), else 0.
// It only ever opposes penetration, so it is dissipative.
// Signature: translational residuals trend with |V_in|^2; penetration saturates with speed.
#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"cd", "kg/m", 0.0, 5000.0, 0.0, 0.0, true, "drag coefficient m/d1 (0 = no drag)",
     ParameterRole::kDragCoefficient},
};

// Signature: the residual and parameter trends of this family (docs/effects/inertial_drag.md,
// "Signature in residuals", which gives the physical reasoning and the literature).
constexpr SignatureTrend kSignature[] = {
    {"residual vy", "speed_in"},
    {"residual vx", "speed_in"},
    {"residual penetration", "speed_in"},
    {"param restitution", "speed_in"},
};

class InertialDrag final : public Effect {
 public:
  std::string_view name() const override { return "inertial_drag"; }
  std::string_view summary() const override {
    return "speed-squared drag against penetration (Poncelet, Katsuragi-Durian)";
  }
  std::string_view equation() const override {
    return "fn += cd * vn^2 if vn < 0 (penetrating), else 0";
  }
  std::string_view reference() const override {
    return "Katsuragi & Durian (2007) Nature Physics 3, 420-423";
  }
  Stage stage() const override { return Stage::kNormal; }
  LawKind kind() const override { return {Family::kDrag, Variable::kNormalSpeed}; }
  Signature signature() const override {
    return {"inertial drag of the sand (a force growing with the speed squared)", kSignature};
  }
  std::span<const ParameterSpec> parameters() const override { return kParams; }

  void apply(const ContactBatch& c, const double* const* p, double* const*) const override {
    const double* __restrict cd = p[0];
    const double* __restrict vn = c.vn;
    const double* __restrict active = c.active;
    double* __restrict fn = c.fn;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      const double v = vn[i] < 0.0 ? vn[i] : 0.0;
      fn[i] += active[i] > 0.0 ? cd[i] * v * v : 0.0;
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_inertial_drag() {
  return std::make_unique<InertialDrag>();
}

}  // namespace ricochet::effects
