// An independent truth for the detection benchmark (issue 10, item 5): a second implementation
// of the paper's contact law for the lab cylinder, written from the notes' description and
// sharing NO code with the engine it tests (it links only the impact-set writer), with its own
// integrator, time step and stiffnesses, hidden physics in forms that the engine's catalog does
// not use, release-to-release scatter of the ground and lab-like measurement noise.
//
// What differs from the engine (calibration/engine, docs/diagnosis.md):
//   integrator   semi-implicit (symplectic) Euler         engine: velocity Verlet
//   time step    2e-6 s                                   engine: 1e-5 s
//   stiffness    kn = kt = 3e7 N/m, kr = 5e7 N m/rad       engine: 1e7, 1e7, 1e8
//   contact      disc on flat ground, lever l = R - h, unloading fn = e_n^2 kn h (notes)
//   end          contact over and the block rising clear of the ground
// Hidden physics (strength s multiplies a reference strength; s = 1 is literature-based where a
// literature value exists):
//   crsp_restitution   e_n^2 / (1 + s (v_n0 / 9.144 m/s)^2)^2, v_n0 the impact normal speed
//                      (Pfeiffer & Bowen 1989, CRSP; RocFall's "scale R_n by velocity")
//   kd_drag            normal force s (40 kg/m) v_n^2 while the block moves into the sand
//                      (Katsuragi & Durian 2007, Nature Physics 3, 420: m/d1 ~ rho_g x projected
//                      area, about 40 kg/m for the lab cylinder at 1 cm depth, notes)
//   spin_rolling       mu_R (1 + s 0.01 s/rad |omega|): rolling resistance growing with spin (no
//                      literature value: 0.01 s/rad is +65 % at the lab's 65 rad/s)
//   depth_friction_exp mu (1 + s (h / 3 mm)^2): friction hardening quadratic in depth (the
//                      catalog's form is linear; 3 mm is the overlap scale of this stiffness)
//   rankine_plough     horizontal force -sign(v_x) s 1/2 K_p gamma h^2 L, K_p = 3.7,
//                      gamma = 15.7 kN/m^3, L = 0.29 m (Rankine passive pressure, notes): about
//                      0.08 N at 3 mm, physically invisible in rebound velocities
//   none, two (crsp_restitution and spin_rolling at the same strength)
// Scatter per release: e_n^2 ~ U(0.12, 0.20), mu ~ U(0.25, 0.45), mu_R ~ U(0.12, 0.20) (narrow
// ranges around the paper's Table 4 cylinder row). Noise: V_out (0.05 m/s, 0.03 m/s, 2 rad/s),
// V_in (0.05 m/s, 0.05 m/s, 1.4 rad/s), Gaussian. No uncertainty columns are written and only
// velocities (the lab's observables): the diagnosis must assume its own noise scale.
// Randomness: std::mt19937_64 with hand-written uniform and Box-Muller draws (bit-reproducible
// on one machine for a given seed).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "impact/impact_set.hpp"

namespace ricochet::truth {

/// The families of hidden physics (file comment).
enum class Family {
  kNone,
  kCrspRestitution,
  kKdDrag,
  kSpinRolling,
  kDepthFrictionExp,
  kRankinePlough,
  kTwo
};
const std::vector<std::string>& family_names();
/// Throws std::invalid_argument listing the accepted names.
Family family_from_name(const std::string& name);
/// The reference strength in words and physical units (for docs and provenance).
std::string reference_strength(Family family);

/// Whether a diagnosed candidate (an effect name, or "a+b" for a pair) names the hidden
/// family: the benchmark's one definition of "the right family" (docs/detection-benchmark.md).
///   crsp_restitution    rate_restitution, en2_* laws
///   kd_drag             inertial_drag
///   spin_rolling        muR_spin_* laws
///   depth_friction_exp  depth_friction, mu_penetration_* laws
///   rankine_plough      ploughing
///   two                 either of crsp_restitution's or spin_rolling's
/// A pair names a family when one of its effects does.
bool names_family(Family family, const std::string& candidate);

/// One release's ground and the hidden effect's strength.
struct Ground {
  double en2 = 0.16, mu = 0.35, muR = 0.16;
  Family family = Family::kNone;
  double strength = 0;
};

/// V_out of one collision of the lab cylinder (m/s, m/s, rad/s); status false when the block
/// never rebounds within 0.2 s.
struct Rebound {
  std::array<double, 3> vout{};
  bool ok = false;
};
Rebound collide(const std::array<double, 3>& vin, const Ground& g);

enum class Design { kLab, kWide };

struct SetOptions {
  Family family = Family::kNone;
  double strength = 1.0;
  std::size_t n = 40;
  Design design = Design::kLab;
  std::uint64_t seed = 1;
  /// Incident states of the lab design (their V_in are resampled with a Gaussian kernel).
  std::vector<std::array<double, 3>> lab_vin;
};

struct TruthSet {
  ImpactSet set;         ///< measured set, no truth inside
  nlohmann::json truth;  ///< settings, per-release ground, effect size
  /// Mean and RMS shift of each V_out component (with the effect minus without it, same states
  /// and ground, no noise) [m/s, m/s, rad/s].
  std::array<double, 3> mean_shift{}, rms_shift{};
};
TruthSet make_set(const SetOptions& options);

}  // namespace ricochet::truth
