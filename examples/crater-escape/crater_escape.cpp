// `crater_escape`: a rebound threshold. On a bed that keeps its crater the block must climb out of
// the hole it dug before it flies, which costs about the same energy at every impact speed, so the
// restitution GROWS with the impact speed and vanishes below a threshold: the stick/bounce form
// of Thornton and Ning (1998), e^2 = e0^2 (1 - (v_s / v)^2), where a constant energy per unit mass
// is lost whatever the speed. Written smooth, so that the neutral value 0 recovers the paper's
// constant e_n^2 and the score test has a slope there:
//   e_n^2_eff = e_n^2 * v0^2 / (v0^2 + vc2),   v0 = largest approach speed of this contact so far;
// for v0^2 >> vc2 the rebound energy is e_n^2 (v0^2 - vc2) / 2 per unit mass: a barrier of
// e_n^2 vc2 / 2 J/kg. For scale: climbing out of a crater of depth d costs g d per unit mass
// (d = 16 mm on the default resolved bed: 0.16 J/kg), i.e. vc2 of order 2 g d / e_n^2.
// Found missing by the diagnosis on the resolved campaigns (docs/diagnosis.md, "On the third
// calibrated bed": e_n^2 rising with |V_in|, r = 0.91), and written as a user would: a plugin
// (docs/tutorial-effect.md), loaded with --plugin; the ladder on those campaigns is in
// docs/diagnosis.md, "Adding the missing effect". Signature: per-release e_n^2 and the V_out^y
// residual rising with the impact speed and the penetration.
//   ricochet ladder data/resolved/speeds-cdt.h5 --shape cylinder --add crater_escape
//       --plugin build/examples/crater-escape/libcrater_escape.so
#include <memory>

#include "effects/effect.hpp"
#include "effects/registry.hpp"

namespace {

using ricochet::ContactBatch;
using ricochet::Effect;
using ricochet::ParameterSpec;
using ricochet::Signature;
using ricochet::SignatureTrend;
using ricochet::Stage;
using ricochet::StateSpec;

constexpr ParameterSpec kParams[] = {
    {"vc2", "m^2/s^2", 0.0, 9.0, 0.0, 0.0, true,
     "squared escape speed: e_n^2 halves at an approach speed of sqrt(vc2) (0 = no threshold)"},
};
constexpr StateSpec kState[] = {{"v0", "m/s"}};

constexpr SignatureTrend kSignature[] = {
    {"residual vy", "abs_vin_y"},
    {"param restitution", "abs_vin_y"},
    {"param restitution", "penetration"},
};

class CraterEscape final : public Effect {
 public:
  std::string_view name() const override { return "crater_escape"; }
  std::string_view summary() const override {
    return "rebound threshold: restitution grows with impact speed (escape from the crater)";
  }
  std::string_view equation() const override {
    return "en2_eff = en2 * v0^2 / (v0^2 + vc2),  v0 = max approach speed -vn of the contact";
  }
  std::string_view reference() const override {
    return "Thornton & Ning (1998) Powder Technol. 99, 154 (stick/bounce threshold); "
           "docs/diagnosis.md (resolved campaigns)";
  }
  Stage stage() const override { return Stage::kCoefficient; }
  ricochet::LawKind kind() const override {
    return {ricochet::Family::kRestitution, ricochet::Variable::kImpactSpeed};
  }
  Signature signature() const override {
    return {"restitution growing with impact speed (rebound threshold)", kSignature};
  }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  std::span<const StateSpec> state() const override { return kState; }

  void apply(const ContactBatch& c, const double* const* p, double* const* s) const override {
    const double* __restrict vc2 = p[0];
    double* __restrict v0 = s[0];
    const double* __restrict vn = c.vn;
    const double* __restrict active = c.active;
    double* __restrict enf = c.en2_factor;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      const double v = ricochet::hold_max_approach(v0[i], vn[i], active[i]);
      const double v2 = v * v;
      // At contact onset v0 can be 0 for a step: the factor is then 1 if vc2 = 0, else 0.
      const double denom = v2 + vc2[i];
      enf[i] *= denom > 0.0 ? v2 / denom : 1.0;
    }
  }
};

}  // namespace

// The plugin's entry point: Ricochet calls it after dlopen (EffectRegistry::load_plugin).
extern "C" void ricochet_register_effects(ricochet::EffectRegistry& registry) {
  registry.add(std::make_unique<CraterEscape>());
}
