// An independent truth for the detection benchmark (issue 10, item 5;
// docs/detection-benchmark.md): a second implementation of the paper's contact law for the lab
// cylinder, written from the paper's equations (Garcia et al. 2020, Eqs. 3, 5 and 6, as
// docs/effects/normal.md, tangential.md and rolling.md state them) and sharing NO code with the
// engine it tests: this library links only the impact-set writer (ricochet_impact) and never
// includes calibration/engine or calibration/effects. It has its own integrator, time step,
// stiffnesses and lever arm, hidden physics (some families in forms no catalog candidate has;
// kd_drag, rankine_plough and spin_rolling in a candidate's form: docs/detection-benchmark.md),
// release-to-release scatter of the ground and lab-like measurement noise, so that a diagnosis
// tested on its sets is not an inverse crime.
//
// What differs from the engine (calibration/engine/engine.hpp) and why:
//   integrator  semi-implicit (symplectic) Euler: v += a dt, then x += v dt   engine: velocity
//   Verlet time step   2e-6 s                                                          engine: 1e-5
//   s stiffness   kn = kt = 3e7 N/m, kr = 5e7 N m/rad                             engine: 1e7, 1e7,
//   1e8 lever arm   l = R - h (contact point on the ground surface)   engine: R - h/2 (mid-overlap)
//   end         first step out of contact with the centre rising (a disc on flat ground then
//               has a positive ballistic clearance for ever)   engine: re-contact prediction
// The stiffnesses are within the range a calibration could not tell apart on rebound velocities
// (the law's V_out depends weakly on them), so the law is "the same physics, another code".
//
// The law (paper Eq. 3, 5, 6), per step with overlap h = R - y > 0:
//   normal     loading (h grows): fn += kn dh; unloading: fn = min(fn, e_n^2 kn h); fn >= 0
//   tangential ft -= kt v_t dt, |ft| <= mu F_n, v_t = v_x + omega l (bottom-point slip)
//   rolling    M -= kr omega dt, |M| <= mu_R l F_n
// with F_n = fn (+ the Katsuragi-Durian drag when that family is on). Out of contact all three
// are zero and their history cleared.
//
// Hidden physics (strength s >= 0 multiplies the family's reference strength; s = 0 is exactly
// the paper's law; s = 1 is literature-based where the literature gives a value):
//   crsp_restitution    e_n^2 -> e_n^2 / (1 + s (v_n0 / v_c)^2)^2, v_c = 9.144 m/s, v_n0 the
//                       impact normal speed: R_n / (1 + (v_n / 9.144 m/s)^2) (Pfeiffer & Bowen
//                       1989, CRSP; RocFall's "scale R_n by velocity"), squared because e_n^2 is
//                       an energy restitution; s scales 1 / v_c^2.
//   kd_drag             F_n += s (m/d1) v_y^2 while the block moves into the sand (v_y < 0, h > 0),
//                       zero while it comes out; m/d1 = 40 kg/m (Katsuragi & Durian 2007, Nature
//                       Physics 3, 420: m z'' = m g - k z - (m/d1) z'^2, m/d1 ~ rho_g x projected
//                       area = 1600 kg/m^3 x 0.08 m x 0.29 m at 1 cm). The drag is a normal
//                       force of the sand, so it also raises the Coulomb and rolling caps.
//   spin_rolling        mu_R -> mu_R (1 + s c_w |omega|), c_w = 0.008 s/rad: no literature
//                       value; chosen so that s = 1 moves the mean V_out by the lab's Table 1
//                       scale on the lab design (independent_truth --calibrate-shift: s = 1.0).
//   depth_friction_exp  mu -> mu (1 + s (h / h_mu)^2), h_mu = 3 mm (quadratic: the catalog's
//                       depth_friction is linear, its generated mu_penetration laws linear or a
//                       power of h / 3 mm); no literature value (RAMMS::ROCKFALL's scarring is
//                       a depth-dependent friction without a number for sand); 3 mm is the
//                       overlap scale of the paper's stiffness.
//   rankine_plough      F_x -= sign(v_x) s 1/2 K_p gamma h^2 L, K_p = 3.7 (Rankine,
//                       tan^2(45 + 35/2 deg)), gamma = 15.7 kN/m^3, L = 0.29 m
//                       (data/shapes/cylinder.toml): about 0.02 N at this code's 1.6 mm overlap, 1
//                       N at 1 cm: physically invisible in rebound velocities (measured anyway).
//   two                 crsp_restitution and spin_rolling, each at s times its own reference.
// Three more whose exact form no candidate has (issue 31, 5c):
//   depth_speed_drag    F_n += s c_hv h v_y^2 while penetrating (v_y < 0): a drag whose
//                       coefficient grows with the depth of sand set in motion; c_hv = 40 kg/m /
//                       3 mm = 1.33e4 kg/m^2 (Katsuragi-Durian's m/d1 reached at 3 mm overlap).
//                       The catalog's inertial_drag is v^2 alone; no law is h v^2.
//   yield_restitution   e_n^2 -> e_n^2 min(1, (v_yield / v_n0)^(s/2)), v_yield = 2 m/s:
//                       constant below the yield speed, e ~ v^(-s/4) above (Thornton & Ning
//                       1998, Powder Technol. 99:154, elastic-plastic impact, e ~ (v_y/v)^(1/4)
//                       at s = 1); the generated en2 laws are linear or power laws in v0
//                       without the yield threshold; 2 m/s is a lab-range choice.
//   slip_spin_friction  mu -> mu (1 + s c_sw |v_t| |omega|), c_sw = 2e-3 s^2/(m rad): a
//                       friction that grows with the product of slip and spin (no literature
//                       value: s = 1 raises mu by 30 % at the lab's mean state, |v_t| 2.3 m/s
//                       and |omega| 65 rad/s; no generated law has a product of two variables).
//   rate_threshold_drag F_n += s c_rt (|v_y| - v_th)^2 while the block penetrates faster than
//                       v_th = 2 m/s, c_rt = 100 kg/m: a drag that the sand only raises above a
//                       rate (no literature value; at 4 m/s, 400 N, as the Katsuragi-Durian
//                       drag's 40 kg/m at 3.2 m/s). The library's drags (-c v_n|v_n|, -c v_n,
//                       -c h v_n|v_n|) have no threshold.
// Scatter per release (the paper's stochastic premise: every release meets another patch of
// sand): e_n^2 ~ U(0.12, 0.20), mu ~ U(0.25, 0.45), mu_R ~ U(0.12, 0.20), narrow ranges around
// the paper's Table 4 cylinder row (0.15 +- 0.06, 0.23 +- 0.11, 0.16 +- 0.04). Noise (Gaussian,
// 1 sd): V_in (0.05 m/s, 0.05 m/s, 1.4 rad/s), V_out (0.05 m/s, 0.03 m/s, 2 rad/s). Observables:
// velocities only, no uncertainty columns (like the lab): the diagnosis assumes its own noise.
// With SetOptions::contact_features also the maximum overlap (`penetration`) and the contact
// duration, each with Gaussian noise (default the lab-scale estimates of 0.5 mm and 1 ms,
// diagnosis::NoiseSpec::lab()), as a resolved campaign or an instrumented lab would have them:
// the sets of the stiffness identifiability study (docs/diagnosis.md, "Which stiffnesses the
// contact features identify").
// Randomness: one std::mt19937_64 per set with hand-written uniform (top 53 bits) and
// Box-Muller normal draws, in a fixed order per release, so a set is bit-for-bit reproducible
// from its seed (std:: distributions are not specified bit for bit across libraries).
//
// The oracle's ceiling (docs/detection-benchmark.md, "The oracle's ceiling"): the power of the
// best test there is for "effect present" against "absent" once the paper's constants (e_n^2, mu,
// mu_R) are re-estimated. The issue asks for >= 90 % detection at the lab scale; if this test
// cannot reach it, no diagnosis can. The oracle knows the hidden effect's exact shape per
// release, delta_i = V_out(with effect) - V_out(without) at the noise-free true V_in and the
// release's own ground (3-vector: m/s, m/s, rad/s), and the exact error covariance
//   Sigma_i = N_out + G_i C G_i^T + J_i N_in J_i^T                                  [1]
// with N_out, N_in the V_out and V_in noise covariances (diagonal, the sds above), C the
// variances of the uniform ground scatter ((b - a)^2 / 12 per constant), G_i = d V_out /
// d(e_n^2, mu, mu_R) and J_i = d V_out / d V_in at release i (central differences of collide()
// on the law without the effect: steps 2 % of each scatter range and 1/5 of each V_in noise sd).
// The constants are common to all releases, so their re-estimation is a regression on the same
// G_i: with Sigma_i = L_i L_i^T, d = stack(L_i^-1 delta_i), X = stack(L_i^-1 G_i), the part no
// recalibration can absorb is d_perp = (I - X (X^T X)^+ X^T) d (^+: a constant the releases
// cannot move at all is dropped), the noncentrality lambda = |d_perp|^2 and oracle z =
// sqrt(lambda). In this linear-Gaussian model the statistic d_perp^T w / |d_perp| on the whitened
// residuals w is N(0, 1) without the effect and N(z, 1) with it, so its one-sided power is
//   P = Phi(z - z_{1-alpha})                                                       [2]
// and by the Neyman-Pearson lemma (Lehmann & Romano, Testing Statistical Hypotheses, 3rd ed.,
// Thm 3.2.1; invariance under the nuisance constants: ibid. ch. 6) no level-alpha test of the
// simple alternative beats it. Assumptions: V_out is linear in the constants and V_in over the
// scatter and noise, errors Gaussian (the ground scatter is uniform, the caps switch on and off,
// and delta_i varies with the ground draw: a Monte Carlo check of the statistic on this
// simulator, docs, found [2] at or above its power in 12 of 13 cells, so the ceiling is
// optimistic); in the oracle's favour: the effect's shape and size are known (a diagnosis must
// search over shapes: the Bonferroni family below) and so are the noise and scatter covariances
// (a diagnosis estimates them).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "impact/block_track.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::truth {

/// The lab cylinder (paper Fig. 4 caption; data/shapes/cylinder.toml): radius [m], mass [kg],
/// inertia [kg m^2], length [m] (solid concrete cylinder with I = m R^2 / 2).
inline constexpr double kRadius = 0.08, kMass = 13.9, kInertia = 0.0445, kLength = 0.29;

/// The families of hidden physics (file comment).
enum class Family {
  kNone,
  kCrspRestitution,
  kKdDrag,
  kSpinRolling,
  kDepthFrictionExp,
  kRankinePlough,
  kTwo,
  // Forms that no candidate of the catalog or the generated laws has (issue 31, 5c):
  kDepthSpeedDrag,    ///< a drag growing with depth times speed squared
  kYieldRestitution,  ///< restitution constant below a yield speed, a power law above
  kSlipSpinFriction,  ///< friction growing with the product of slip speed and spin
  // A force term outside the force-residual library's shapes (issue 33, item 4):
  kRateThresholdDrag,  ///< a drag that switches on above a penetration speed
};
/// "none", "crsp_restitution", "kd_drag", "spin_rolling", "depth_friction_exp",
/// "rankine_plough", "two", "depth_speed_drag", "yield_restitution", "slip_spin_friction",
/// "rate_threshold_drag" (the enum's order).
const std::vector<std::string>& family_names();
/// Throws std::invalid_argument naming the accepted names.
Family family_from_name(const std::string& name);
const std::string& family_name(Family family);

/// A family's reference strength (s = 1) in physical units, next to the literature's value.
struct Reference {
  std::string parameter;   ///< e.g. "v_c"
  double value = 0;        ///< at s = 1
  std::string unit;        ///< e.g. "m/s"
  std::string literature;  ///< the literature's value and source, or why there is none
};
Reference reference(Family family);
/// One line: "v_c = 9.144 m/s (CRSP, Pfeiffer & Bowen 1989)".
std::string reference_strength(Family family);

/// The benchmark's ONE mapping from a diagnosed candidate to a family of physics
/// (docs/detection-benchmark.md, "Which candidate names which family"):
///   rate_restitution, en2_* laws        -> "restitution"
///   inertial_drag                       -> "drag"
///   muR_spin_* laws                     -> "spin rolling"
///   depth_friction, mu_penetration_*    -> "depth friction"
///   ploughing                           -> "ploughing"
///   mu_slip_speed_*, mu_spin_* laws     -> "slip friction"
///   anything else (stiffness laws, other coefficient laws, plugins) -> "other"
std::string candidate_family(const std::string& effect);
/// The families a hidden family should be found as ("two": restitution and spin rolling).
std::vector<std::string> expected_families(Family family);
/// Whether a diagnosed candidate (an effect, or "a+b" for a pair) names the hidden family:
/// one of its effects maps (candidate_family) to one of expected_families(family).
bool names_family(Family family, const std::string& candidate);

/// One release's ground and the hidden effect's strength.
struct Ground {
  double en2 = 0.16, mu = 0.35, muR = 0.16;
  Family family = Family::kNone;
  double strength = 0;
};

/// This code's numerics (file comment); tests change them (e.g. gravity off, the engine's
/// stiffness and step) to check the law itself.
struct Numerics {
  double dt = 2e-6;           ///< [s]
  double kn = 3e7, kt = 3e7;  ///< [N/m]
  double kr = 5e7;            ///< [N m/rad]
  double gravity = 9.81;      ///< [m/s^2]
  double max_time = 0.2;      ///< a rebound not over by then fails [s]
};

/// One collision of the lab cylinder.
struct Rebound {
  std::array<double, 3> vout{};  ///< at the end of contact (m/s, m/s, rad/s)
  bool ok = false;               ///< false: no rebound within Numerics::max_time
  double peak_overlap = 0;       ///< largest h [m] (not an observable of the sets)
  double duration = 0;           ///< first touch to end of contact [s]
};
/// One sample of a collision's time series while in contact (issue 33: the force-residual
/// discovery's data). The contact point's state and the forces on the block (contact frame:
/// normal up, tangent +x; moment counter-clockwise), and the hidden law's additive force, the
/// residual a perfect model of the paper's law would leave: the Katsuragi-Durian and depth-speed
/// drags (normal) and the Rankine ploughing (tangential). Families that modify a coefficient
/// (restitution, friction, rolling resistance) add no separable force: NaN there.
struct TraceSample {
  double t_s = 0, h_m = 0, vn_mps = 0, vt_mps = 0, vx_mps = 0, omega_radps = 0;
  bool loading = false;
  double fn_N = 0, ft_N = 0, moment_Nm = 0;
  double hidden_fn_N = 0, hidden_ft_N = 0;
};

/// One record of the collision as a tracked history (the columns of a LIGGGHTS track,
/// impact/block_track.hpp): the block's centre, angle and velocities at the start of a step, and
/// the contact force and torque about the centre of mass of that step (gravity excluded; zero
/// out of contact), in the paper frame on the ground y = 0. x and theta start at 0.
struct PathSample {
  double t_s = 0, x_m = 0, y_m = 0, theta_rad = 0, vx_mps = 0, vy_mps = 0, w_radps = 0;
  double fx_N = 0, fy_N = 0, torque_Nm = 0;
};

/// `trace`: when given, the contact's samples every `trace_every` steps are appended. `path`:
/// when given, a record every `trace_every` steps from the start (0.1 um above the ground, before
/// the contact) to the end of the contact.
Rebound collide(const std::array<double, 3>& vin, const Ground& ground,
                const Numerics& numerics = {}, std::vector<TraceSample>* trace = nullptr,
                long trace_every = 100, std::vector<PathSample>* path = nullptr);

/// The engine's step and stiffnesses (calibration/engine: dt 1e-5 s, kn = kt = 1e7 N/m,
/// kr = 1e8 N m/rad; the paper's values), for sets that differ from it only in the integrator,
/// lever arm and end of contact.
inline constexpr Numerics kEngineNumerics{1e-5, 1e7, 1e7, 1e8, 9.81, 0.2};

/// kGiven: the incident states of SetOptions::given_vin, in order (a plan of throws from
/// `ricochet design`), one release each; the ground, the noise and the effect as in the others.
enum class Design { kLab, kWide, kGiven };

/// The oracle's one-sided level for one pre-specified hypothesis (file comment).
inline constexpr double kOracleAlpha = 0.05;
/// Default size of the oracle's Bonferroni family, alpha / 45: an example of the diagnosis's
/// candidate family (docs/detection-benchmark.md: "Holm over 45+ candidates"); a parameter
/// (SetOptions::oracle_family_size, independent_truth --family-size).
inline constexpr std::size_t kOracleFamilySize = 45;
/// Power of the one-sided oracle test with noncentrality z at level alpha in (0, 1):
/// Phi(z - z_{1-alpha}) (file comment, [2]), Phi(x) = erfc(-x / sqrt 2) / 2 and z_{1-alpha} by
/// bisection on erfc. Throws std::invalid_argument for alpha outside (0, 1).
double oracle_power(double z, double alpha);

struct SetOptions {
  Family family = Family::kNone;
  /// This code's numerics (the default: another step and stiffness than the engine's);
  /// kEngineNumerics makes the null truth the engine's law in another integrator only.
  Numerics numerics;
  double strength = 1.0;
  std::size_t n = 40;
  Design design = Design::kLab;
  std::uint64_t seed = 1;
  /// Incident states of the lab design (a smoothed bootstrap: a lab state drawn at random plus
  /// a Gaussian kernel of Silverman's bandwidth per component). Required for Design::kLab.
  std::vector<std::array<double, 3>> lab_vin;
  std::string lab_source;  ///< where lab_vin came from (provenance only)
  /// Ground scatter, uniform per release: e_n^2, mu, mu_R in [lo, hi]. Default: the benchmark's
  /// narrow ranges (file comment); kScatterLabLo/Hi have the lab's own spread (issue 31, 5d/5f).
  std::array<double, 3> scatter_lo = {0.12, 0.25, 0.12}, scatter_hi = {0.20, 0.45, 0.20};
  /// The true incident states of Design::kGiven (n is their number); ids `id_prefix` + index.
  std::vector<std::array<double, 3>> given_vin;
  std::string id_prefix = "T";
  /// Also compute the effect's part that a recalibration of the law's constants cannot absorb
  /// (TruthSet::residual_rms; about 0.3 s for 40 releases) and, for a family other than none,
  /// the oracle's z (TruthSet::oracle_z; 12 collisions per release).
  bool refit = true;
  /// Size of the Bonferroni family for the oracle's family power (alpha / size).
  std::size_t oracle_family_size = kOracleFamilySize;
  /// Also write `penetration` (Rebound::peak_overlap) and `contact_duration` (Rebound::duration)
  /// with Gaussian noise of these standard deviations [m], [s]; their two normal draws come
  /// after a release's velocity noise, so a set without them is unchanged bit for bit. A
  /// release whose noisy penetration or duration is not positive is drawn again.
  bool contact_features = false;
  double noise_penetration_m = 0.5e-3;
  double noise_contact_duration_s = 1e-3;
  /// Also keep each release's tracked history (TruthSet::tracks): a record every 0.2 ms from
  /// before the contact to its end (PathSample), the contact force with white noise of sd
  /// `track_force_noise_N` on each component (an assumption, as force_sets.hpp's; positions and
  /// velocities exact), no torque. The noise has its own generator (seed ^ kTrackSeedSalt), so
  /// the set's velocities are the same bit for bit with or without tracks.
  bool tracks = false;
  double track_force_noise_N = 50.0;
};
inline constexpr std::uint64_t kTrackSeedSalt = 0x747261636bULL;  // "track"

/// The lab's own release-to-release scatter (paper Table 4's cylinder spread as the lab data
/// give it: e_n^2 sd 0.045, mu_R sd 0.2 about 0.26, docs/diagnosis.md "The lab data"), as
/// uniform ranges of those sds: e_n^2 U(0.08, 0.24) (sd 0.046), mu U(0.25, 0.45), mu_R
/// U(0.02, 0.62) (sd 0.17: a uniform of sd 0.2 about 0.26 would reach below 0).
inline constexpr std::array<double, 3> kScatterLabLo = {0.08, 0.25, 0.02};
inline constexpr std::array<double, 3> kScatterLabHi = {0.24, 0.45, 0.62};

struct TruthSet {
  ImpactSet set;         ///< the measured set (noisy velocities only, no truth inside)
  nlohmann::json truth;  ///< every setting, per-release truth, effect sizes (provenance)
  /// Effect size in physical units: mean and RMS over releases of V_out with the effect minus
  /// V_out without it (same incident states and ground draws, no noise) [m/s, m/s, rad/s].
  std::array<double, 3> mean_shift{}, rms_shift{};
  /// The same after the best common change of (e_n^2, mu, mu_R) on the law without the effect
  /// (least squares in lab-scale units): what no recalibration of the paper's constants can
  /// explain, hence the most any diagnosis can see. Zero when SetOptions::refit is false.
  std::array<double, 3> residual_rms{};
  /// The oracle's z = sqrt(lambda) (file comment, [1]-[2]): 0 for none, or when
  /// SetOptions::refit is false. The provenance's "oracle" holds it with its powers.
  double oracle_z = 0;
  /// SetOptions::tracks: one per release, in set order (block_mass_kg the cylinder's 13.9 kg).
  std::vector<BlockTrack> tracks;
};
TruthSet make_set(const SetOptions& options);

/// The lab's measurement scale (paper Table 1): 0.1 m/s, 0.1 m/s, 3.4 rad/s.
inline constexpr std::array<double, 3> kLabScale = {0.1, 0.1, 3.4};
/// max_k |mean_shift[k]| / kLabScale[k].
double shift_in_lab_units(const std::array<double, 3>& mean_shift);
/// The strength at which the effect's mean V_out shift first reaches the lab scale
/// (shift_in_lab_units = 1), for the options' design, n and seed: geometric bracketing from
/// s = 1, then bisection to a relative width of 1e-3 (the shift is not monotonic for every
/// family, so this is a crossing, not necessarily the only one). Throws for "none" and when no
/// strength up to 1e6 reaches the scale.
double lab_scale_strength(SetOptions options);

/// The incident states (V_in^x, V_in^y, omega_in) of the cylinder releases of the impact set at
/// `path`: SetOptions::lab_vin of the lab design (data/lab/cylinders.csv in the studies).
std::vector<std::array<double, 3>> lab_cylinder_states(const std::string& path);

}  // namespace ricochet::truth
