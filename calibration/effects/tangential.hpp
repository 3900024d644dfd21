// The per-lane equation of the effect `tangential` (tangential.cpp declares the rest). One
// equation, two drivers: the effect's batch loop and the engine's fused kernel for the paper's
// law (engine/paper_kernel.hpp). T is double or a GCC vector.
#pragma once

#include "effects/effect.hpp"

namespace ricochet::effects {

struct TangentialLaw {
  /// New tangential force [N] from its previous value fs [N], the stiffness kt [N/m], mu [-],
  /// the contact point's tangential speed vt [m/s], the normal force fn [N], whether the slot is
  /// in contact (active > 0), the coefficient stage's mu factor mf (1 in the paper's law) and
  /// the step dt [s]. Garcia et al. (2020) Eq. 5: incremental spring, Coulomb cap mu mf fn.
  template <class T>
  static T force(T fs, T kt, T mu, T vt, T fn, T active, T mf, double dt) {
    const T trial = fs - kt * vt * dt;
    const T f = clamp_abs(trial, mu * mf * fn);
    return active > 0.0 ? f : lane_fill<T>(0.0);
  }
};

}  // namespace ricochet::effects
