// `tangential`: incremental tangential spring capped by Coulomb friction (Garcia et al. 2020,
// Eq. 5). mu "includes friction and other dissipation mechanisms acting in the tangential
// direction" (paper section 4.1).
#include "effects/tangential.hpp"

#include <memory>

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"kt", "N/m", 1e5, 1e9, 1e7, NAN, false, "tangential stiffness",
     ParameterRole::kTangentialStiffness, IdentifiedBy::kNothing},
    {"mu", "-", 0.0, 2.0, 0.23, NAN, true, "friction coefficient (Coulomb cap)",
     ParameterRole::kFrictionCap},
};
constexpr StateSpec kState[] = {{"ft", "N"}};

class Tangential final : public Effect {
 public:
  std::string_view name() const override { return "tangential"; }
  std::string_view summary() const override {
    return "incremental tangential spring kt, capped by mu*fn (Coulomb)";
  }
  std::string_view equation() const override {
    return "ft <- clamp(ft - kt*vt*dt, -mu*mf*fn, +mu*mf*fn)";
  }
  std::string_view reference() const override {
    return "Garcia et al. (2020) JGR Earth Surf. 125, Eq. 5; Richefeu & Villard (2016)";
  }
  Stage stage() const override { return Stage::kTangential; }
  LawKind kind() const override { return {Family::kSlidingFriction, Variable::kNone}; }
  Signature signature() const override { return {"the paper's tangential friction (Eq. 5)", {}}; }
  FusedLaw fused_law() const override { return FusedLaw::kPaperTangential; }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  std::span<const StateSpec> state() const override { return kState; }

  void apply(const ContactBatch& c, const double* const* p, double* const* s) const override {
    const double* __restrict kt = p[0];
    const double* __restrict mu = p[1];
    double* __restrict fs = s[0];
    const double* __restrict vt = c.vt;
    const double* __restrict muf = c.mu_factor;
    const double* __restrict fn = c.fn;
    const double* __restrict active = c.active;
    double* __restrict ft = c.ft;
    const double dt = c.dt;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      fs[i] = TangentialLaw::force(fs[i], kt[i], mu[i], vt[i], fn[i], active[i], muf[i], dt);
      ft[i] += fs[i];
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_tangential() {
  return std::make_unique<Tangential>();
}

}  // namespace ricochet::effects
