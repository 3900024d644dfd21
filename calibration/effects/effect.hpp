// A physical effect at a block-ground contact: the building block of every contact law.
//
// The paper's law (Garcia et al. 2020, Eq. 3, 5, 6) is three effects: `normal`, `tangential`,
// `rolling`. Candidate missing physics (speed-dependent restitution, inertial drag, ploughing,
// depth-hardening friction, penetration-dependent stiffness) are further effects. A model is an
// ordered composition of effects (effects/model.hpp); no law is ever a copy of another.
//
// An effect is one class in one file (effects/<name>.cpp) that declares everything the rest of
// the toolkit knows about it:
//  - its parameters: name, SI unit, bounds, nominal value, neutral value (where it does nothing),
//    role (a stiffness, a friction cap, a restitution, ...) and what in an impact set identifies
//    it: the engine, the fit, the diagnosis and the uncertainty module ask for roles, never for
//    names;
//  - its per-contact state (history variables, cleared by the engine when contact is lost);
//  - its equation and reference (shown by `ricochet effects` and in docs/effects/<name>.md);
//  - its stage, its kind (what the law changes and what it depends on), its signature (what its
//    absence looks like, in the words of the signature vocabulary below), whether it is one of
//    the engine's inlined laws (fused_law) and how stiff it can make the contact
//    (max_stiffness_factor);
// and implements apply(), which adds forces and moments at one contact slot for a batch of lanes.
// The registry (effects/registry.hpp) checks the declaration when it stores the effect, plugins
// included.
//
// Batches: the engine integrates many collisions at once ("lanes"), structure-of-arrays, so that
// apply() is a plain loop over lanes that the compiler vectorises. Write apply() branch-free
// (use ternaries), with no allocation and no virtual calls inside the loop.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace ricochet {

/// What a parameter is to the rest of the toolkit. The stable time step (critical_time_step)
/// reads the stiffnesses, the engine's fused kernel the paper's six parameters, the fit's
/// identifiability statements the caps, the diagnosis the calibrated parameters its signature
/// trends name ("param restitution"), the Monte Carlo the paper's ranges: all by role.
enum class ParameterRole {
  kOther = 0,            ///< none of the roles below
  kNormalStiffness,      ///< a normal contact stiffness [N/m] (the paper's kn)
  kTangentialStiffness,  ///< a tangential spring [N/m] (kt)
  kRollingStiffness,     ///< a rolling spring [N m/rad] (kr)
  kRestitution,          ///< the normal energy restitution e_n^2 [-] (en2)
  kFrictionCap,          ///< a Coulomb cap mu fn on the tangential force [-] (mu)
  kRollingCap,           ///< a cap mu_R l fn on the rolling moment [-] (muR)
  kDragCoefficient,      ///< a drag force growing with the speed squared, m/d1 [kg/m]
};
inline constexpr std::size_t kParameterRoleCount = 8;
/// "other", "normal_stiffness", "tangential_stiffness", "rolling_stiffness", "restitution",
/// "friction_cap", "rolling_cap", "drag_coefficient": the words of `ricochet effects` and of
/// signature trends ("param restitution").
std::string_view role_name(ParameterRole role);

/// What in an impact set identifies a parameter's value. It decides, for every effect alike,
/// which parameters a fit calibrates beyond the flagged ones (fit::calibration_model) and
/// which fixed ones the diagnosis's score test projects off (diagnosis/signature.hpp).
enum class IdentifiedBy {
  /// The rebound velocities (Eq. 7): fitted whenever ParameterSpec::calibrated says so.
  kRebound = 0,
  /// Only the contact features (maximum penetration, contact duration): fixed by default; a fit
  /// whose error compares those features calibrates it within its bounds, and on a set of
  /// velocities only the score test projects its direction off, so that a wrong value does not
  /// read as missing physics. The paper's kn (docs/diagnosis.md, "Which stiffnesses the contact
  /// features identify").
  kContactFeatures,
  /// Nothing the impact sets measure: a numerical or reference constant, fixed unless a model
  /// file says otherwise (the paper's kt and kr, hertz_stiffness's h_ref).
  kNothing,
};
inline constexpr std::size_t kIdentifiedByCount = 3;
/// "rebound", "contact_features", "nothing".
std::string_view identified_by_name(IdentifiedBy by);

/// A parameter of an effect. Names are unique within a model (the registry checks this).
/// Plugins written before roles existed still compile: the last two fields default to
/// {kOther, kRebound}.
struct ParameterSpec {
  std::string_view name;         ///< e.g. "en2"; used in TOML files, --set, JSON, HDF5
  std::string_view unit;         ///< SI unit, "-" for dimensionless
  double lower;                  ///< smallest allowed value (inclusive)
  double upper;                  ///< largest allowed value (inclusive)
  double nominal;                ///< default value
  double neutral;                ///< value at which the effect does nothing; NaN if none
  bool calibrated;               ///< fitted by calibration by default (stiffnesses are not)
  std::string_view description;  ///< one line, shown in listings
  ParameterRole role = ParameterRole::kOther;           ///< what the parameter is (ParameterRole)
  IdentifiedBy identified_by = IdentifiedBy::kRebound;  ///< what identifies it (IdentifiedBy)
};

/// A per-contact history variable of an effect (e.g. the incremental normal force).
struct StateSpec {
  std::string_view name;
  std::string_view unit;
};

/// Order in which effects act within one time step. Coefficient effects modify the factors read
/// by force effects (e.g. friction hardening scales mu); normal effects set the normal force that
/// tangential and rolling caps use; body effects act at the centre of mass.
enum class Stage { kCoefficient = 0, kNormal = 1, kTangential = 2, kRolling = 3, kBody = 4 };
inline constexpr std::size_t kStageCount = 5;
std::string_view stage_name(Stage stage);

/// Structure-of-arrays view of ONE contact slot (one vertex of the block's shape) across `n`
/// lanes, for one time step. Contact frame: n = ground normal (up), t = tangent (+x on flat
/// ground). Lanes with active[i] == 0 are out of contact: effects must add no force there.
struct ContactBatch {
  std::size_t n = 0;  ///< number of lanes
  double dt = 0;      ///< time step [s]

  // Kinematics (read only).
  const double* active = nullptr;  ///< 1 in contact (overlap h > 0), 0 otherwise
  const double* h = nullptr;       ///< penetration (overlap) [m], 0 out of contact
  const double* dh = nullptr;      ///< penetration increment over this step [m] (>0 loading)
  const double* vn = nullptr;      ///< normal velocity of the contact point [m/s], <0 = into ground
  const double* vt = nullptr;      ///< tangential (sliding) velocity of the contact point [m/s]
  const double* w = nullptr;       ///< block angular velocity relative to ground [rad/s]
  const double* lever = nullptr;   ///< l: distance contact point - centre of mass [m] (Eq. 6)
  const double* vx = nullptr;      ///< block centre velocity, x [m/s]
  const double* vy = nullptr;      ///< block centre velocity, y [m/s]
  double mass = 0;                 ///< block mass [kg]
  double length = 0;               ///< block length along its axis [m] (for per-length laws)

  // Coefficient factors: 1 at the start of each step, multiplied by coefficient-stage effects,
  // read by force effects.
  double* kn_factor = nullptr;       ///< multiplies the incremental loading stiffness kn
  double* elastic_factor = nullptr;  ///< Phi(h) / (kn h): elastic force at h relative to linear
  double* en2_factor = nullptr;      ///< multiplies e_n^2
  double* mu_factor = nullptr;       ///< multiplies mu
  double* muR_factor = nullptr;      ///< multiplies mu_R

  // Forces, accumulated by the effects of each stage (contact frame / body frame).
  double* fn = nullptr;       ///< normal force on the block [N], >= 0 pushes the block out
  double* ft = nullptr;       ///< tangential force on the block [N], along t
  double* moment = nullptr;   ///< resisting moment on the block [N m], counter-clockwise +
  double* fx_body = nullptr;  ///< force at the centre of mass, x [N]
  double* fy_body = nullptr;  ///< force at the centre of mass, y [N]

  // The ground's surface under this slot, for models with an effect whose moves_surface() is
  // true (nullptr otherwise): how far it stands above the undisturbed ground [m]. `lift` is the
  // surface this step's h, dh and active were measured from (read only; h - lift is the vertex's
  // depth below the undisturbed ground); such an effect writes `lift_next` (starting from
  // `lift`), the surface of the next step. The engine zeroes both when the contact is lost.
  const double* lift = nullptr;
  double* lift_next = nullptr;
};

/// The largest approach speed -v_n of a contact so far [m/s], held in the state slot `v0` and
/// cleared out of contact: laws that depend on the impact's speed read it, not the current normal
/// velocity (which passes through zero at the deepest point). Branch-free, for apply() loops.
inline double hold_max_approach(double& v0, double vn, double active) {
  const double v = v0 > -vn ? v0 : -vn;
  v0 = active > 0.0 ? v : 0.0;
  return v0;
}

/// The loading factor of a stiffness law whose loading force is kn Psi(h): the secant of Psi over
/// the step, so that `normal`'s incremental loading telescopes to exactly kn Psi(h); `fallback`
/// for a step too small for a secant (|dh| <= 1e-8 h: its force increment vanishes with it).
/// `held` is Psi at the previous step (0 at contact onset, as h is), updated here and cleared out
/// of contact. Branch-free, for apply() loops.
inline double step_secant(double& held, double psi_h, double dh, double h, double active,
                          double fallback) {
  const double secant = std::fabs(dh) > 1e-8 * h ? (psi_h - held) / dh : fallback;
  held = active > 0.0 ? psi_h : 0.0;
  return secant;
}

/// The signature vocabulary: what the diagnosis computes trends of (diagnosis/trends.hpp), one
/// quantity of the base model against one impact feature. Effects declare their trends in its
/// words (SignatureTrend); the registry parses them when it stores the effect and refuses a
/// word outside it, naming the word and listing the known ones.
///
/// Quantities: the held-out residual (measured - predicted) of an observable, or a per-release
/// calibrated parameter of the base model, named by its role.
enum class TrendQuantity {
  kResidualVx = 0,           ///< "residual vx"
  kResidualVy,               ///< "residual vy"
  kResidualW,                ///< "residual w"
  kResidualPenetration,      ///< "residual penetration"
  kResidualContactDuration,  ///< "residual contact_duration"
  kParameter,                ///< "param <role>", e.g. "param restitution" (role_name)
};
inline constexpr std::size_t kResidualQuantityCount = 5;
/// The word of a residual quantity ("residual vy"); "param" for kParameter.
std::string_view quantity_name(TrendQuantity quantity);

/// Impact features: measured on the set, or simulated by the calibrated model where the set
/// lacks them (penetration, contact duration, alpha_in).
enum class ImpactFeature {
  kSpeedIn = 0,      ///< "speed_in": |V_in| [m/s]
  kAbsVinY,          ///< "abs_vin_y": |V_in^y| [m/s]
  kVinX,             ///< "vin_x": V_in^x [m/s]
  kWin,              ///< "win": omega_in [rad/s]
  kImpactAngle,      ///< "impact_angle": incidence angle of V_in below the horizontal [deg]
  kAlphaIn,          ///< "alpha_in": the block's orientation at impact [deg]
  kPenetration,      ///< "penetration": the maximum penetration [mm]
  kContactDuration,  ///< "contact_duration": the contact duration [ms]
};
inline constexpr std::size_t kImpactFeatureCount = 8;
std::string_view feature_name(ImpactFeature feature);

/// One trend that the diagnosis expects when this effect is missing from a model, declared in
/// words: quantity "residual vx" | "residual vy" | "residual w" | "residual penetration" |
/// "residual contact_duration" | "param <role>" (a calibrated base parameter of that role, e.g.
/// "param restitution"); feature one of feature_name()'s words.
struct SignatureTrend {
  std::string_view quantity;
  std::string_view feature;
};

/// A SignatureTrend parsed into the vocabulary's enums.
struct ExpectedTrend {
  TrendQuantity quantity = TrendQuantity::kResidualVx;
  ParameterRole parameter = ParameterRole::kOther;  ///< for kParameter: the parameter's role
  ImpactFeature feature = ImpactFeature::kSpeedIn;
};
/// Parses a declared trend. Throws std::invalid_argument "unknown signature quantity 'X'; known
/// quantities: ..." or "unknown signature feature 'X'; known features: ...".
ExpectedTrend parse_trend(const SignatureTrend& trend);

/// What an effect stands for and what its absence looks like (its signature): the diagnosis
/// tests these trends and cites them as evidence; each built-in's page in docs/effects/ gives
/// their physical reasoning and the literature behind it.
struct Signature {
  std::string_view meaning;                ///< in words, e.g. "speed-dependent restitution"
  std::span<const SignatureTrend> trends;  ///< empty for the paper's own law
  /// Contact features (penetration, duration) are biased when the effect is missing.
  bool contact_bias = false;
};

/// What an effect's law changes (issue 31): the diagnosis's confidence set names these families,
/// so that laws that the data cannot tell apart are grouped by the physics they stand for.
enum class Family {
  kNone = 0,           ///< the law as it stands, nothing added (the confidence set's "none")
  kRestitution,        ///< the normal energy restitution e_n^2
  kSlidingFriction,    ///< the Coulomb friction mu
  kRollingResistance,  ///< the rolling resistance mu_R
  kStiffness,          ///< the contact's normal stiffness or its elastic curve
  kDrag,               ///< a velocity-dependent resisting force (inertial or viscous drag)
  kPloughing,          ///< a force from the sand pushed ahead of the block
  kOther,              ///< none of the above
};
inline constexpr std::size_t kFamilyCount = 8;
/// "none", "restitution", "sliding_friction", "rolling_resistance", "stiffness", "drag",
/// "ploughing", "other" (the JSON words of docs/commands/diagnose.md).
std::string_view family_name(Family family);

/// What an effect's law depends on (issue 31).
enum class Variable {
  kNone = 0,        ///< a constant
  kImpactSpeed,     ///< the contact's (largest) approach speed
  kNormalSpeed,     ///< the current normal velocity of the contact
  kPenetration,     ///< the overlap h
  kSpin,            ///< the block's angular velocity
  kSlipSpeed,       ///< the sliding speed of the contact point
  kIncidenceAngle,  ///< the angle of the incident velocity
  kOther,           ///< none of the above
};
inline constexpr std::size_t kVariableCount = 8;
/// "none", "impact_speed", "normal_speed", "penetration", "spin", "slip_speed",
/// "incidence_angle", "other".
std::string_view variable_name(Variable variable);

/// The family and the variable of an effect's law (Effect::kind()).
struct LawKind {
  Family family = Family::kOther;
  Variable variable = Variable::kOther;
};

/// The engine's inlined laws (engine/paper_kernel.hpp): a model that holds all three, on flat
/// ground, runs in the fused kernel, which computes these equations itself instead of calling
/// apply(). An effect that declares one computes exactly that per-lane equation in its apply(),
/// declares the parameters of its roles once each and keeps the force in its first state
/// variable (the registry checks the roles and the state; the test
/// Engine.FusedKernelIsTheGenericPathBitForBit the bits).
enum class FusedLaw {
  kNone = 0,         ///< called through apply()
  kPaperNormal,      ///< NormalLaw::force: kNormalStiffness, kRestitution; state fn [N]
  kPaperTangential,  ///< TangentialLaw::force: kTangentialStiffness, kFrictionCap; state ft [N]
  kPaperRolling,     ///< RollingLaw::moment: kRollingStiffness, kRollingCap; state M [N m]
};
inline constexpr std::size_t kFusedLawCount = 4;
/// The two parameter roles a fused law reads, in the order of its equation's arguments.
std::array<ParameterRole, 2> fused_law_roles(FusedLaw law);

/// Interface of a physical effect. Implementations are stateless (all history lives in the
/// engine's state arrays), so one instance serves every thread.
class Effect {
 public:
  virtual ~Effect() = default;

  virtual std::string_view name() const = 0;       ///< registry key, e.g. "rolling"
  virtual std::string_view summary() const = 0;    ///< one line
  virtual std::string_view equation() const = 0;   ///< the law in plain text maths
  virtual std::string_view reference() const = 0;  ///< source of the equation
  virtual Stage stage() const = 0;
  virtual std::span<const ParameterSpec> parameters() const = 0;
  virtual std::span<const StateSpec> state() const { return {}; }
  /// The effect's signature (see Signature). Every built-in declares one (tested); a plugin
  /// that does not is diagnosed by its held-out error alone, with summary() as its meaning.
  virtual Signature signature() const { return {}; }
  /// What the law changes and what it depends on (LawKind). Every effect declares it, plugins
  /// included: the diagnosis groups the laws it cannot tell apart by family (issue 31).
  virtual LawKind kind() const = 0;
  /// A member of a generated family (effects/coefficient_law.hpp) rather than a hand-written
  /// effect: the diagnosis screens these before calibrating them, and listings and error
  /// messages give the family by its pattern rather than 40 names.
  virtual bool generated() const { return false; }
  /// Whether `diagnose` tries it when it is missing from the model and no candidates are named.
  /// The force terms (effects/force_term.hpp) are not tried: the force-residual discovery finds
  /// them from contact histories, and the rebound screen's family stays what it was.
  virtual bool default_candidate() const { return true; }
  /// Which inlined law of the engine this effect is (FusedLaw); kNone for every other effect.
  virtual FusedLaw fused_law() const { return FusedLaw::kNone; }
  /// Whether the effect moves the ground's surface under its contact (ContactBatch::lift_next):
  /// the sand it heaps up, which the block then stands on. A model with such an effect is
  /// integrated on the engine's generic path, never the fused kernel.
  virtual bool moves_surface() const { return false; }
  /// The largest factor [-] by which this effect multiplies the normal loading stiffness
  /// (ContactBatch::kn_factor) at any penetration up to `max_penetration_m` [m], given its
  /// parameter values `values` (declaration order). critical_time_step multiplies the model's
  /// normal stiffness by the product over its effects. Default 1: the effect does not stiffen
  /// the contact (a factor below 1 only lengthens the stable step, so it need not be declared).
  virtual double max_stiffness_factor(std::span<const double> values,
                                      double max_penetration_m) const {
    (void)values;
    (void)max_penetration_m;
    return 1.0;
  }
  /// The largest stiffness [N/m] this effect adds to the normal contact as a force of its own
  /// (d(force)/dh, not a factor on kn), at any penetration up to `max_penetration_m` [m], given
  /// its values: critical_time_step adds it to the model's stiffest normal spring. Default 0.
  virtual double max_added_stiffness(std::span<const double> values,
                                     double max_penetration_m) const {
    (void)values;
    (void)max_penetration_m;
    return 0.0;
  }
  /// The effect as a law with numbers and units, e.g.
  /// "mu_R = mu_R0 (1 + c |omega|), c = 0.012 s/rad". `values`: this effect's parameters in
  /// declaration order. Default: equation() followed by "name = value unit" for each parameter.
  virtual std::string law(std::span<const double> values) const;

  /// Adds this effect's contribution at one contact slot for all lanes of `c`.
  /// params[k][i]: value of the k-th declared parameter in lane i.
  /// state[j][i]: the j-th declared state variable of this slot in lane i (zero when the contact
  /// starts; the engine zeroes it when the contact is lost).
  virtual void apply(const ContactBatch& c, const double* const* params,
                     double* const* state) const = 0;
};

/// Put RICOCHET_SIMD before an effect's lane loop: it tells the compiler the lane arrays do not
/// overlap so the loop vectorises (OpenMP SIMD; needs -fopenmp-simd, which the build sets).
#define RICOCHET_SIMD _Pragma("omp simd")

/// Helpers for branch-free effect code. T is double or a GCC vector of doubles (the engine's
/// fused kernel, engine/paper_kernel.hpp): the same expression serves both, ternaries rather
/// than std::fmin/fmax, which are library calls that block vectorisation.
template <class T>
inline T clamp_abs(T x, T limit) {
  const T lo = x < -limit ? -limit : x;
  return lo > limit ? limit : lo;
}
/// std::max and std::min's exact semantics ((a < b) ? b : a and (b < a) ? b : a) for T.
template <class T>
inline T lane_max(T a, T b) {
  return a < b ? b : a;
}
template <class T>
inline T lane_min(T a, T b) {
  return b < a ? b : a;
}
/// A lane value of T filled with `v` (v itself for double).
template <class T>
inline T lane_fill(double v) {
  return T{} + v;
}

}  // namespace ricochet
