// A user-written effect, compiled as a plugin: angle-dependent restitution for grazing impacts
// (a restitution law in the incidence angle, which the built-in catalog does not hold). Beladjine
// et al. (2007, Phys. Rev. E 75, 061305) measured that grains hitting a granular bed at a grazing
// angle rebound with a larger restitution than head-on ones. Written with the impact angle theta of
// each contact, taken at the contact's onset (tan theta = |vn| / |vt|):
//   e_n^2_eff = e_n^2 * (1 + kg * cos^2(theta))     (clamped at 1 by the `normal` effect)
// kg = 0 recovers the paper's law.
//
// Walkthrough: docs/tutorial-effect.md. Build: this folder's CMakeLists.txt. Use:
//   ricochet simulate --plugin ./libgrazing_restitution.so --add grazing_restitution --set kg=0.5
//   ...
#include <cmath>
#include <memory>

#include "effects/effect.hpp"
#include "effects/registry.hpp"

namespace {

constexpr ricochet::ParameterSpec kParams[] = {
    {"kg", "-", 0.0, 5.0, 0.0, 0.0, true, "grazing gain of e_n^2 (0 = angle-independent)"},
};
constexpr ricochet::StateSpec kState[] = {{"cos2", "-"}};
// What the diagnosis should see when the effect is missing: the calibrated e_n^2 and the
// V_out^y residual trending with the incidence angle (words of docs/effects/README.md).
constexpr ricochet::SignatureTrend kTrends[] = {{"param restitution", "impact_angle"},
                                                {"residual vy", "impact_angle"}};

class GrazingRestitution final : public ricochet::Effect {
 public:
  std::string_view name() const override { return "grazing_restitution"; }
  std::string_view summary() const override {
    return "grazing impacts rebound more (angle-dependent restitution)";
  }
  std::string_view equation() const override {
    return "en2_eff = en2 * (1 + kg * cos^2(theta)),  tan(theta) = |vn| / |vt| at contact onset";
  }
  std::string_view reference() const override {
    return "Beladjine, Ammi, Oger & Valance (2007) Phys. Rev. E 75, 061305";
  }
  // A coefficient effect: it scales e_n^2, which the `normal` effect then reads.
  ricochet::Stage stage() const override { return ricochet::Stage::kCoefficient; }
  ricochet::LawKind kind() const override {
    return {ricochet::Family::kRestitution, ricochet::Variable::kIncidenceAngle};
  }
  ricochet::Signature signature() const override { return {"grazing restitution", kTrends}; }
  std::span<const ricochet::ParameterSpec> parameters() const override { return kParams; }
  std::span<const ricochet::StateSpec> state() const override { return kState; }

  void apply(const ricochet::ContactBatch& c, const double* const* p,
             double* const* s) const override {
    const double* __restrict kg = p[0];
    double* __restrict cos2 = s[0];
    const double* __restrict vn = c.vn;
    const double* __restrict vt = c.vt;
    const double* __restrict active = c.active;
    double* __restrict enf = c.en2_factor;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      // The state is zero until the first contact step, then keeps the onset angle.
      const double speed2 = vn[i] * vn[i] + vt[i] * vt[i];
      const double onset = speed2 > 0.0 ? vt[i] * vt[i] / speed2 : 0.0;
      const double value = cos2[i] > 0.0 ? cos2[i] : onset;
      cos2[i] = active[i] > 0.0 ? value : 0.0;
      enf[i] *= 1.0 + kg[i] * cos2[i];
    }
  }
};

}  // namespace

// The plugin's entry point: Ricochet calls it after dlopen (EffectRegistry::load_plugin).
extern "C" void ricochet_register_effects(ricochet::EffectRegistry& registry) {
  registry.add(std::make_unique<GrazingRestitution>());
}
