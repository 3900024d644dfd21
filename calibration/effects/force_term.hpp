// Force terms: the dimensioned library of the force-residual discovery (issue 33), and each term
// as an effect, so that a law discovered from contact histories goes into a model file and
// through `calibrate`, `diagnose`, `ladder`, `montecarlo` and `sobol` like any other effect.
//
// A term adds c x(state) to one component of the contact's action on the block: the normal force,
// the tangential force or the moment. Each is neutral at c = 0 and signed so that c > 0 resists
// the motion (a drag, a stiffening): the sign of a discovered coefficient says whether it is one.
//
// Frames and signs: the contact frame of effects/effect.hpp (ContactBatch). h >= 0 is the
// penetration [m], v_n the normal velocity of the contact point (< 0 into the ground) [m/s], v_t
// its sliding velocity [m/s], v_x the block centre's velocity along the tangent [m/s], omega the
// block's spin [rad/s]. The terms (the literature law each is, where it is one):
//   normal:     c h (Katsuragi & Durian 2007's k z; a linear spring), c h^1.5 (Hertz), c h^2,
//               -c v_n|v_n| (Poncelet / Katsuragi-Durian inertial drag, c = m/d1 [kg/m]),
//               -c v_n (viscous), -c h v_n|v_n| (depth-growing drag), c h sign(-v_n) (hysteresis:
//               a stiffer loading than unloading branch, Walton & Braun 1986)
//   tangential: -c sign(v_x) h^2 (Rankine passive ploughing against the centre's motion, as the
//               catalog's `ploughing` effect), -c sign(v_t) h, -c v_t (viscous), -c v_t|v_t|
//   moment:     -c sign(omega) h, -c omega
//
// As effects (the family `term_<name>`, e.g. term_inertial_drag, parameter c_<name>): a normal
// term acts in the normal stage after the law before it and keeps the normal force unilateral
// (fn = max(fn + c x, 0): dry sand does not pull the block in); a tangential term adds to the
// tangential force after the friction cap (ploughing is not friction), except the ploughing
// term, which pushes at the centre of mass against its motion (body stage, as the catalog's
// `ploughing`: power -c h^2 |v_x| <= 0); a moment term adds to the rolling moment after its cap. The discovery reads the deepest contact slot; an effect acts at
// every slot in contact: the two agree when one slot touches (a disc always, a prism except on a
// face). Bounds: c >= 0 for every term but the elastic curves (c h, c h^1.5, c h^2), since a
// negative drag or hysteresis would make energy that no passive bed gives; |c| up to the value that
// makes the term 3e4 N (a moment term 2.4e3 N m) at the reference state h = 3 mm, |v_n| = 2.5 m/s,
// |v_t| = |v_x| = 1 m/s, |omega| = 40 rad/s: the paper's kn = 1e7 N/m at the 3 mm overlap, about 3
// x the largest contact force of the resolved lab cylinders (11 kN, data/resolved/lab-cylinders.h5
// scaled to the lab block), and that force at the cylinder's 0.08 m radius. They are not default
// candidates of `diagnose`'s rebound screen (Effect::default_candidate): the force-residual
// discovery finds them from histories.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "effects/effect.hpp"

namespace ricochet::effects {

/// The contact's state at one instant (contact frame, SI; file comment).
struct ContactSample {
  double h_m = 0;          ///< penetration, >= 0
  double vn_mps = 0;       ///< normal velocity of the contact point, < 0 into the ground
  double vt_mps = 0;       ///< sliding velocity of the contact point
  double vx_mps = 0;       ///< the block centre's velocity along the tangent (what ploughs)
  double omega_radps = 0;  ///< the block's angular velocity
  bool loading = false;    ///< the penetration grows at this instant
};

/// Which part of the contact's action a term adds to.
enum class ForceComponent { kNormal = 0, kTangential = 1, kMoment = 2 };
inline constexpr std::size_t kForceComponents = 3;
std::string_view component_name(ForceComponent c);  ///< "normal", "tangential", "moment"

/// One term of the library (file comment).
struct ForceTerm {
  std::string_view name;  ///< e.g. "inertial_drag"
  ForceComponent component;
  std::string_view expression;  ///< e.g. "-c v_n|v_n|"
  std::string_view unit;        ///< SI unit of its coefficient c, e.g. "kg/m"
  std::string_view literature;  ///< the law it is, e.g. "Poncelet / Katsuragi-Durian drag"; "" none
  LawKind kind;                 ///< the family and variable of the law (diagnosis's grouping)
  /// A function of h alone (an elastic curve): either sign of c is passive. Every other term
  /// dissipates for c > 0 and would make energy for c < 0, so its effect takes c >= 0 only.
  bool elastic;
  double (*value)(const ContactSample&);  ///< the term per unit coefficient, in N or N m
  /// The largest stiffness d(term)/dh per unit coefficient at a penetration up to h [m]
  /// (critical_time_step); nullptr for a term that is not a spring.
  double (*stiffness)(double h_m) = nullptr;
  /// Applied at the centre of mass as a body force along x (the catalog's `ploughing` does the
  /// same): a force against the centre's motion at the contact point would do positive work on a
  /// back-spinning block, whose contact point slips backwards.
  bool at_centre = false;
};

/// The library, in a fixed order.
const std::vector<ForceTerm>& force_terms();
/// The library's terms of one component, in library order.
std::vector<const ForceTerm*> force_terms(ForceComponent c);
/// The term of that name, or nullptr.
const ForceTerm* find_force_term(std::string_view name);

/// The term's effect name, "term_<name>", and its parameter, "c_<name>".
std::string force_term_effect_name(const ForceTerm& term);
std::string force_term_parameter_name(const ForceTerm& term);
/// The bound of |c| (file comment), in the term's unit: the effect's bounds are [-bound, bound]
/// for an elastic term, [0, bound] for the others.
double force_term_bound(const ForceTerm& term);

/// The term as an effect (file comment).
std::unique_ptr<Effect> make_force_term(const ForceTerm& term);
/// Every term as an effect, library order (the registry's family).
std::vector<std::unique_ptr<Effect>> make_force_term_effects();

/// "force terms term_<name> with name in {spring, ...}": for error messages and listings.
std::string force_term_family_text();

}  // namespace ricochet::effects
