// A classical RK4 step of a 1-D penetration z'' = acc(z, z') (z the depth, positive down): the
// synthetic drops of the granular-fit tests (Katsuragi & Durian 2007, Nature Physics 3, 420,
// Eq. 1) integrate their law with it, independently of the fits they check.
#pragma once

namespace ricochet::dem::test {

/// Advances (z [m], v [m/s]) by dt [s] under acc(z, v) [m/s^2].
template <class Acc>
void rk4_step(double& z, double& v, double dt, const Acc& acc) {
  const double k1z = v, k1v = acc(z, v);
  const double k2z = v + 0.5 * dt * k1v, k2v = acc(z + 0.5 * dt * k1z, k2z);
  const double k3z = v + 0.5 * dt * k2v, k3v = acc(z + 0.5 * dt * k2z, k3z);
  const double k4z = v + dt * k3v, k4v = acc(z + dt * k3z, k4z);
  z += dt / 6 * (k1z + 2 * k2z + 2 * k3z + k4z);
  v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

}  // namespace ricochet::dem::test
