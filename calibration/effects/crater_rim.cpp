// `crater_rim`: the rim of sand a block pushes up ahead of itself, and climbs. A block that moves
// along the ground while it is below the surface sweeps the sand ahead into a heap; the heap
// lifts the block, and the contact goes on while the block rises above the undisturbed level:
// the roll-out of the resolved sand bed, whose block leaves about a centimetre above the level
// after penetrating 4 mm (docs/resolved-model.md, "The verification"; docs/diagnosis.md, "The
// force-residual discovery": what the flat ground of `crater_ramp` cannot hold).
//
// Per contact (2-D, per unit length of the block), with L the surface's height above the
// undisturbed ground under the contact (ContactBatch::lift, zero when the contact starts) and
// d = h - L the contact's depth below the undisturbed ground:
//   A  <- A + max(d, 0) |v_x| dt              sand swept ahead [m^2 per m of block]
//   L' =  min(sqrt(2 tan_phi A), L + tan_phi |v_x| dt)   while fn <= w_rim m g, else L' = L
//   F_x,body += -sign(v_x) sigma fn,   sigma = (L' - L) / (|v_x| dt)   (0 <= sigma <= tan_phi)
// The swept sand stands as a heap with a face at slope tan_phi against the block (cross-section
// H^2 / (2 tan_phi) = A); the surface under the contact rises to its height, no faster than
// that slope along the travel, and only while the block presses on it with at most w_rim times
// its weight: loose sand heaped ahead carries about the block's weight and yields beyond it (the
// resolved block is carried out of its crater by a force of about its weight, docs/resolved-
// model.md; without the bound the heap, a rigid surface, could push with any force, and along a
// measured path that the model does not follow it does: docs/diagnosis.md, "Added: the rim").
// The rising surface loads the normal spring by fn dL; the reaction sigma fn, the normal force
// turned back by the slope the block climbs, takes the same work from the horizontal motion, so
// the rim turns horizontal motion into lift and makes no energy (to first order in dt: the
// reaction reads this step's fn, the spring the next step's). Applied at
// the centre of mass, as `ploughing` and `crater_ramp`. The contact ends when the block leaves
// the heaped surface, and the heap with it.
//
// The heap at the angle of repose is the bulldozing picture of wheel-soil and ploughing
// mechanics (Bekker 1969, "Introduction to terrain-vehicle systems", bulldozing resistance;
// Wong 2008, "Theory of ground vehicles", 4th ed., chapter 2); RAMMS::ROCKFALL's scarring
// model keeps the scar a block leaves in soil (Lu et al. 2019). Signature: the base model's
// contacts too short and V_out^y too low, the more the block travels in its crater (faster
// V_in^x).
#include <cmath>
#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {
namespace {

constexpr ParameterSpec kParams[] = {
    {"tan_phi", "-", 0.0, 1.2, 0.6, 0.0, true,
     "slope of the heaped sand's face (the sand's angle of repose; 0 = no rim)"},
    {"w_rim", "-", 0.1, 100.0, 1.0, NAN, false,
     "the most the heap carries, in block weights: pressed harder it yields and does not rise",
     ParameterRole::kOther, IdentifiedBy::kContactFeatures},
};
constexpr double kG = 9.81;  // [m/s^2], the block's weight m g
constexpr StateSpec kState[] = {{"A", "m^2"}};

// Signature (docs/effects/crater_rim.md, "Signature in residuals").
constexpr SignatureTrend kSignature[] = {
    {"residual contact_duration", "vin_x"},
    {"residual vy", "vin_x"},
};

class CraterRim final : public Effect {
 public:
  std::string_view name() const override { return "crater_rim"; }
  std::string_view summary() const override {
    return "the rim of sand heaped ahead of the block: the surface under the contact rises and "
           "the block climbs it";
  }
  std::string_view equation() const override {
    return "A <- A + max(h - L, 0)*|vx|*dt; L' = min(sqrt(2*tan_phi*A), L + tan_phi*|vx|*dt) "
           "while fn <= w_rim*m*g, else L' = L; Fx_body += -sign(vx)*fn*(L' - L)/(|vx|*dt) (L: "
           "the surface's height above the undisturbed ground under the contact, L' the next "
           "step's)";
  }
  std::string_view reference() const override {
    return "Bekker (1969) Introduction to terrain-vehicle systems (bulldozing); Wong (2008) "
           "Theory of ground vehicles, 4th ed., ch. 2 (bulldozing resistance); Lu et al. (2019) "
           "Landslides 16:2353 "
           "(rockfall scarring in soil)";
  }
  Stage stage() const override { return Stage::kBody; }
  LawKind kind() const override { return {Family::kPloughing, Variable::kOther}; }
  Signature signature() const override {
    return {"the rim of sand heaped ahead of the block (roll-out above the level)", kSignature,
            true};
  }
  // A contact geometry named by the force-residual discovery (docs/diagnosis.md), added by hand
  // like crater_ramp, so that every documented diagnosis's family of candidates stays what it was.
  bool default_candidate() const override { return false; }
  bool moves_surface() const override { return true; }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  std::span<const StateSpec> state() const override { return kState; }

  void apply(const ContactBatch& c, const double* const* p, double* const* st) const override {
    const double* __restrict tp = p[0];
    const double* __restrict wr = p[1];
    double* __restrict area = st[0];
    const double* __restrict h = c.h;
    const double* __restrict vx = c.vx;
    const double* __restrict fn = c.fn;
    const double* __restrict active = c.active;
    const double* __restrict lift = c.lift;
    double* __restrict lift_next = c.lift_next;
    double* __restrict fx = c.fx_body;
    const double dt = c.dt;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      const bool on = active[i] > 0.0;
      const double travel = (vx[i] >= 0.0 ? vx[i] : -vx[i]) * dt;
      const double depth = h[i] - lift[i];
      const double a = area[i] + (depth > 0.0 ? depth : 0.0) * travel;
      const double heap = std::sqrt(2.0 * tp[i] * a);
      const double climb = lift[i] + tp[i] * travel;
      const double next = heap < climb ? heap : climb;
      // The heap carries at most w_rim block weights: pressed harder it yields (it does not rise).
      const bool carries = fn[i] <= wr[i] * c.mass * kG;
      const double rise = carries && next > lift[i] ? next - lift[i] : 0.0;
      const double slope = travel > 0.0 ? rise / travel : 0.0;
      fx[i] -= on ? (vx[i] >= 0.0 ? 1.0 : -1.0) * slope * fn[i] : 0.0;
      lift_next[i] = on ? lift[i] + rise : 0.0;
      area[i] = on ? a : 0.0;
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_crater_rim() {
  return std::make_unique<CraterRim>();
}

}  // namespace ricochet::effects
