// The per-lane equation of the effect `normal` (normal.cpp declares the rest: parameters, state,
// reference, signature). One equation, two drivers: the effect's batch loop and the engine's
// fused kernel for the paper's law (engine/paper_kernel.hpp). T is double or a GCC vector.
#pragma once

#include "effects/effect.hpp"

namespace ricochet::effects {

struct NormalLaw {
  /// New normal force [N] of one contact from its previous value fs [N], the stiffness kn [N/m],
  /// e_n^2 [-], the overlap h and its increment dh [m] over the step, whether the slot is in
  /// contact (active > 0) and the coefficient stage's factors (1 in the paper's law).
  /// Garcia et al. (2020) Eq. 3-4: incremental loading, direct unloading onto the
  /// e_n^2-scaled elastic curve; min() equals the paper's direct assignment (fn never lies below
  /// that curve before unloading) and keeps the law dissipative when coefficient effects change
  /// the factors during the contact.
  template <class T>
  static T force(T fs, T kn, T en2, T dh, T h, T active, T kf, T ef, T enf) {
    const T loading = fs + kn * kf * dh;
    const T en2_eff = lane_min(en2 * enf, lane_fill<T>(1.0));
    const T unloading = lane_min(fs, en2_eff * kn * ef * h);
    const T f = lane_max(dh >= 0.0 ? loading : unloading, lane_fill<T>(0.0));
    return active > 0.0 ? f : lane_fill<T>(0.0);
  }
};

}  // namespace ricochet::effects
