// `crater_ramp`: the front wall of the block's own crater. After its deepest point a block that
// keeps moving along the ground meets the sand it has not displaced yet: the crater's far wall,
// a ramp rising ahead of it. Rolling or sliding up that ramp lifts the block and slows it, and
// keeps it in contact long after a plastic impact: the roll-out of the resolved sand bed
// (docs/resolved-model.md, "The verification": 43-106 ms carried out of the crater by about the
// block's weight), which the paper's law on flat ground cannot make (docs/diagnosis.md, "The
// force-residual discovery": read against flat ground, that force looks like energy made at the
// contact). Per contact, with h_max its deepest overlap so far and s the centre's horizontal
// travel since that depth was reached (reset to 0 while the contact deepens):
//   delta = max(0, tan_beta |s| - (h_max - h))      overlap with a ramp of slope tan_beta [m]
//   F_x,body += -sign(s) tan_beta k_ramp delta,   F_y,body += k_ramp delta
// The force is minus the gradient of 1/2 k_ramp delta^2 in (x, y) (h grows as y falls), so the
// ramp stores energy and gives it back, never makes it; what it holds when the contact ends is
// lost. Applied at the centre of mass: the wall turns horizontal motion into lift, the spin is
// left to the rolling law. Wheel-soil mechanics puts the same reaction on a rolling wheel's
// front arc (Wong & Reece 1967); RAMMS::ROCKFALL's scarring model keeps the scar that the block
// must leave (Lu et al. 2019). Signature: the base model's contacts are too short, and V_out^y
// too low, the more the block travels in its crater (faster V_in^x).
#include <cmath>
#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"tan_beta", "-", 0.0, 1.0, 0.0, 0.0, true,
     "slope of the crater's front wall, rise per metre of travel (0 = flat ground)"},
    {"k_ramp", "N/m", 1e5, 1e9, 1e7, NAN, false,
     "stiffness of the front wall per metre of overlap with it", ParameterRole::kOther,
     IdentifiedBy::kContactFeatures},
};
constexpr StateSpec kState[] = {{"h_max", "m"}, {"s", "m"}};

// Signature (docs/effects/crater_ramp.md, "Signature in residuals").
constexpr SignatureTrend kSignature[] = {
    {"residual contact_duration", "vin_x"},
    {"residual vy", "vin_x"},
};

class CraterRamp final : public Effect {
 public:
  std::string_view name() const override { return "crater_ramp"; }
  std::string_view summary() const override {
    return "the crater's front wall: a ramp ahead of the block lifts it out after its deepest "
           "point";
  }
  std::string_view equation() const override {
    return "delta = max(0, tan_beta*|s| - (h_max - h)); Fx_body += -sign(s)*tan_beta*k_ramp*delta, "
           "Fy_body += k_ramp*delta (h_max: deepest overlap of the contact, s: the centre's "
           "horizontal travel since)";
  }
  std::string_view reference() const override {
    return "Wong & Reece (1967) J. Terramechanics 4(1):81 (front-arc reaction of a wheel in "
           "soil); Lu et al. (2019) Landslides 16:2353 (rockfall scarring in soil)";
  }
  Stage stage() const override { return Stage::kBody; }
  LawKind kind() const override { return {Family::kOther, Variable::kOther}; }
  Signature signature() const override {
    return {"the crater's front wall lifting the block out (roll-out)", kSignature, true};
  }
  // A geometric effect named by the force-residual discovery (docs/diagnosis.md): added by hand
  // (`ladder --add crater_ramp`, `diagnose --candidate crater_ramp`), not tried by default, so that
  // the rebound screen's family and every documented diagnosis stay what they were.
  bool default_candidate() const override { return false; }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  std::span<const StateSpec> state() const override { return kState; }
  double max_added_stiffness(std::span<const double> values, double) const override {
    return values[1] * (1.0 + values[0] * values[0]);
  }

  void apply(const ContactBatch& c, const double* const* p, double* const* st) const override {
    const double* __restrict tb = p[0];
    const double* __restrict k = p[1];
    double* __restrict h_max = st[0];
    double* __restrict s = st[1];
    const double* __restrict h = c.h;
    const double* __restrict vx = c.vx;
    const double* __restrict active = c.active;
    double* __restrict fx = c.fx_body;
    double* __restrict fy = c.fy_body;
    const double dt = c.dt;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      const bool deeper = h[i] >= h_max[i];
      const double hm = deeper ? h[i] : h_max[i];
      const double travel = deeper ? 0.0 : s[i] + vx[i] * dt;
      const double dir = travel >= 0.0 ? 1.0 : -1.0;
      const double rise = tb[i] * (travel >= 0.0 ? travel : -travel) - (hm - h[i]);
      const double f = active[i] > 0.0 && rise > 0.0 ? k[i] * rise : 0.0;
      fx[i] -= dir * tb[i] * f;
      fy[i] += f;
      h_max[i] = active[i] > 0.0 ? hm : 0.0;
      s[i] = active[i] > 0.0 ? travel : 0.0;
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_crater_ramp() {
  return std::make_unique<CraterRamp>();
}

}  // namespace ricochet::effects
