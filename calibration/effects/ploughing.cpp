// `ploughing`: passive earth pressure on the leading face of a penetrating block. Rankine's
// passive force on a wall of width b buried to depth h is P_p = 1/2 K_p gamma h^2 b
// (K_p = tan^2(45 deg + phi/2)). The reduced model's overlap h is a numerical penetration, not
// the physical depth, so the prefactor is lumped into one coefficient cp = 1/2 K_p gamma b
// (h/h_phys)^2:
//   F_x = -cp * h^2 * vx / max(|vx|, v_eps),  applied at the centre of mass.
// Applied at the centre of mass (no moment) so that it can only remove translational energy:
// its power is -cp h^2 |vx| <= 0. v_eps = 0.01 m/s regularises the sign near vx = 0.
// Grows with depth squared, which a Coulomb cap mu*fn cannot represent.
// Signature: V_out^x residual trends with penetration depth and block shape / orientation.
#include <algorithm>
#include <cmath>
#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"cp", "N/m^2", 0.0, 2e9, 0.0, 0.0, true,
     "passive-resistance coefficient 1/2 Kp gamma b, per unit h^2 (0 = none)"},
};
constexpr double kVelocityEpsilon = 0.01;  // m/s

// Signature: the residual and parameter trends of this family (docs/effects/ploughing.md,
// "Signature in residuals", which gives the physical reasoning and the literature).
constexpr SignatureTrend kSignature[] = {
    {"residual vx", "penetration"},
    {"param friction_cap", "penetration"},
    {"param rolling_cap", "penetration"},
};

class Ploughing final : public Effect {
 public:
  std::string_view name() const override { return "ploughing"; }
  std::string_view summary() const override {
    return "passive earth pressure against horizontal motion, growing with depth squared";
  }
  std::string_view equation() const override {
    return "Fx_body += -cp * h^2 * vx / max(|vx|, 0.01 m/s)";
  }
  std::string_view reference() const override {
    return "Rankine passive pressure P_p = 1/2 Kp gamma h^2 b; Garcia et al. (2020) sec. 4.2 "
           "(soil abutment of triangles)";
  }
  Stage stage() const override { return Stage::kBody; }
  LawKind kind() const override { return {Family::kPloughing, Variable::kPenetration}; }
  Signature signature() const override {
    return {"passive earth pressure (ploughing) growing with the depth squared", kSignature};
  }
  std::span<const ParameterSpec> parameters() const override { return kParams; }

  void apply(const ContactBatch& c, const double* const* p, double* const*) const override {
    const double* __restrict cp = p[0];
    const double* __restrict vx = c.vx;
    const double* __restrict h = c.h;
    const double* __restrict active = c.active;
    double* __restrict fx = c.fx_body;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      const double dir = vx[i] / std::max(std::fabs(vx[i]), kVelocityEpsilon);
      fx[i] -= active[i] > 0.0 ? cp[i] * h[i] * h[i] * dir : 0.0;
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_ploughing() {
  return std::make_unique<Ploughing>();
}

}  // namespace ricochet::effects
