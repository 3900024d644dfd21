// The per-lane equation of the effect `rolling` (rolling.cpp declares the rest). One equation,
// two drivers: the effect's batch loop and the engine's fused kernel for the paper's law
// (engine/paper_kernel.hpp). T is double or a GCC vector.
#pragma once

#include "effects/effect.hpp"

namespace ricochet::effects {

struct RollingLaw {
  /// New rolling-resistance moment [N m] from its previous value ms [N m], the stiffness kr
  /// [N m/rad], mu_R [-], the spin w [rad/s], the lever l [m] (contact point to the centre of
  /// mass, paper section 4.1), the normal force fn [N], whether the slot is in contact
  /// (active > 0), the coefficient stage's mu_R factor rf (1 in the paper's law) and the step
  /// dt [s]. Garcia et al. (2020) Eq. 6: incremental spring, capped by mu_R rf l fn.
  template <class T>
  static T moment(T ms, T kr, T muR, T w, T lever, T fn, T active, T rf, double dt) {
    const T trial = ms - kr * w * dt;
    const T m = clamp_abs(trial, muR * rf * lever * fn);
    return active > 0.0 ? m : lane_fill<T>(0.0);
  }
};

}  // namespace ricochet::effects
