// `bearing_yield`: a bed that yields under the block on loading. The loading force saturates with
// depth as the hyperbolic stress-strain curve of soils (Kondner 1963; Duncan & Chang 1970),
//   F_load(h) = kn Psi(h),   Psi(h) = h / (1 + h / h_y),
// tending to the ultimate bearing force kn h_y; unloading is the paper's direct unloading onto a
// straight elastic line through the origin whose slope is the secant at the deepest point,
//   F_unload(h) = e_n^2 kn h / (1 + h_max / h_y),
// so the unloading line stays under the (concave) loading curve: the law never makes energy,
// and a cycle returns e_n^2 x^2 / (2 (1 + x) (x - ln(1 + x))) of the stored energy, x = h_max / h_y
// (e_n^2 at x -> 0, e_n^2 / 2 as x -> infinity): the deeper the bed yields, the more it keeps.
// That is what sets it apart from the catalog's stiffness laws (hertz_stiffness,
// kn_penetration_*), which reshape a nonlinear ELASTIC curve and return e_n^2 whatever the depth.
// Parameter: the inverse yield depth a = 1 / h_y [1/m], neutral 0 (the paper's law bit for bit),
// so that the score test has a derivative there (a cap would not).
// Signature: the restitution falls with the impact speed (deeper contacts yield more); the block
// sinks deeper than the linear spring and stays longer at high speed.
#include <cmath>
#include <memory>

#include "effects/effect.hpp"

namespace ricochet::effects {
namespace {

// Bounds: a = 1e4 1/m is h_y = 0.1 mm, an ultimate force kn h_y of 50 N at the resolved beds'
// kn ~ 5e5 N/m (docs/diagnosis.md), a third of the lab cylinder's weight (136 N): a bed that
// yields at once. The quasi-static bearing capacity of the lab sand under the cylinder's
// footprint (Terzaghi strip footing, B ~ 5 cm, phi ~ 33 deg, N_gamma ~ 30) is about 0.1-0.2 kN,
// so the bound spans it.
constexpr ParameterSpec kParams[] = {
    {"inv_hy", "1/m", 0.0, 1e4, 0.0, 0.0, true,
     "1 / h_y: inverse of the depth at which the loading force is half the spring's (0 = none)",
     ParameterRole::kOther, IdentifiedBy::kRebound},
};
constexpr StateSpec kState[] = {{"psi", "m"}, {"h_max", "m"}};

// Signature: the residual and parameter trends of this family (docs/effects/bearing_yield.md,
// "Signature in residuals").
constexpr SignatureTrend kSignature[] = {
    {"residual vy", "speed_in"},
    {"param restitution", "speed_in"},
    {"residual penetration", "speed_in"},
    {"residual contact_duration", "speed_in"},
};

class BearingYield final : public Effect {
 public:
  std::string_view name() const override { return "bearing_yield"; }
  std::string_view summary() const override {
    return "the bed yields on loading: a hyperbolic force-depth curve and a straight unloading "
           "line";
  }
  std::string_view equation() const override {
    return "loading: fn = kn*Psi(h), Psi(h) = h/(1 + inv_hy*h) (kf = its secant over the step); "
           "unloading: ke = 1/(1 + inv_hy*h_max)";
  }
  std::string_view reference() const override {
    return "Kondner (1963) J. Soil Mech. Found. Div. 89(SM1):115; Duncan & Chang (1970) J. Soil "
           "Mech. Found. Div. 96(SM5):1629 (hyperbolic loading); Thornton (1997) J. Appl. Mech. "
           "64:383 (yield on loading, elastic unloading)";
  }
  Stage stage() const override { return Stage::kCoefficient; }
  LawKind kind() const override { return {Family::kStiffness, Variable::kPenetration}; }
  Signature signature() const override {
    return {"a bed yielding under the block (a force that saturates with depth on loading)",
            kSignature, true};
  }
  // A development-set lead of the force-residual discovery (docs/diagnosis.md), added by hand so
  // that every documented diagnosis's family of candidates stays what it was.
  bool default_candidate() const override { return false; }
  std::span<const ParameterSpec> parameters() const override { return kParams; }
  std::span<const StateSpec> state() const override { return kState; }
  // kf <= 1: it only ever softens the loading spring, so the stable step is the paper's.

  void apply(const ContactBatch& c, const double* const* p, double* const* s) const override {
    const double* __restrict a = p[0];
    double* __restrict psi_prev = s[0];
    double* __restrict h_max = s[1];
    const double* __restrict h = c.h;
    const double* __restrict dh = c.dh;
    const double* __restrict active = c.active;
    double* __restrict kf = c.kn_factor;
    double* __restrict ef = c.elastic_factor;
    RICOCHET_SIMD
    for (std::size_t i = 0; i < c.n; ++i) {
      const double x = h[i];
      const double psi = x / (1.0 + a[i] * x);
      // The secant of Psi over the step (step_secant, as coefficient_law.cpp's integral laws): the
      // loading force of `normal` is exactly kn Psi(h); a step too small takes the tangent at h.
      const double tangent = 1.0 / ((1.0 + a[i] * x) * (1.0 + a[i] * x));
      const double secant = step_secant(psi_prev[i], psi, dh[i], x, active[i], tangent);
      const double deepest = h_max[i] > x ? h_max[i] : x;
      h_max[i] = active[i] > 0.0 ? deepest : 0.0;
      kf[i] *= a[i] != 0.0 ? secant : 1.0;
      ef[i] *= a[i] != 0.0 ? 1.0 / (1.0 + a[i] * deepest) : 1.0;
    }
  }
};

}  // namespace

std::unique_ptr<Effect> make_bearing_yield() {
  return std::make_unique<BearingYield>();
}

}  // namespace ricochet::effects
