// `rolling`: incremental rolling-resistance moment capped by mu_R * l * fn (Garcia et al. 2020,
// Eq. 6). l is the distance from the contact point to the axis through the centre of mass
// (paper section 4.1), supplied by the engine as ContactBatch::lever.
#include "effects/rolling.hpp"

#include <memory>

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"kr", "N m/rad", 1e5, 1e10, 1e8, NAN, false, "rolling stiffness",
     ParameterRole::kRollingStiffness, IdentifiedBy::kNothing},
    {"muR", "-", 0.0, 2.0, 0.16, NAN, true, "rolling-resistance coefficient",
     ParameterRole::kRollingCap},
};
constexpr StateSpec kState[] = {{"M", "N m"}};

class Rolling final : public Effect {
 public:
  std::string_view name() const override { return "rolling"; }
  std::string_view summary() const override {
    return "incremental rolling spring kr, capped by muR*l*fn";
  }
  std::string_view equation() const override {
    return "M <- clamp(M - kr*w*dt, -muR*rf*l*fn, +muR*rf*l*fn)";
  }
  std::string_view reference() const override {
    return "Garcia et al. (2020) JGR Earth Surf. 125, Eq. 6; Richefeu & Villard (2016)";
  }
  Stage stage() const override { return Stage::kRolling; }
  LawKind kind() const override { return {Family::kRollingResistance, Variable::kNone}; }
  Signature signature() const override { return {"the paper's rolling resistance (Eq. 6)", {}}; }
  FusedLaw fused_law() const override { return FusedLaw::kPaperRolling; }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  std::span<const StateSpec> state() const override { return kState; }

  void apply(const ContactBatch& c, const double* const* p, double* const* s) const override {
    const double* __restrict kr = p[0];
    const double* __restrict muR = p[1];
    double* __restrict ms = s[0];
    const double* __restrict w = c.w;
    const double* __restrict rf = c.muR_factor;
    const double* __restrict lever = c.lever;
    const double* __restrict fn = c.fn;
    const double* __restrict active = c.active;
    double* __restrict moment = c.moment;
    const double dt = c.dt;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      ms[i] = RollingLaw::moment(ms[i], kr[i], muR[i], w[i], lever[i], fn[i], active[i], rf[i], dt);
      moment[i] += ms[i];
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_rolling() {
  return std::make_unique<Rolling>();
}

}  // namespace ricochet::effects
