// Generated coefficient laws: any coefficient of the paper's law as a function of a contact or
// impact variable (issue 10: physics beyond the hand-written catalog). One effect class,
// configured by (coefficient, variable, form); the registry holds the whole family (4 x 5 x 2 =
// 40 effects) so that the diagnosis can try each one, and a user can add one by hand:
//
//   effects = ["normal", "tangential", "rolling", "muR_spin_linear"]
// or, in a model file,
//   [[law]]
//   coefficient = "muR"
//   variable = "spin"
//   form = "linear"
//
// Equations (docs/effects/coefficient_law.md):
//   linear:  coefficient_eff = coefficient * (1 + c x),               c [1/unit of x], neutral 0
//   power:   coefficient_eff = coefficient * (max(x, 1e-3 x_ref) / x_ref)^p,   p [-], neutral 0
// the factor clamped to [0.02, 50]. Coefficients: kn (loading stiffness), en2, mu, muR. When a
// kn law's variable is the penetration, the elastic curve of direct unloading is the integral of
// the stiffness law actually applied (floor and clamp included), so a closed cycle still returns
// e_n^2 of the stored energy (paper Eq. 4) for every value within the bounds; with another
// variable the same factor multiplies both. Variables, with their reference x_ref and the upper
// end x_hi of their lab range:
//   approach_speed   v0 = largest -vn of the contact so far [m/s]      x_ref 2.5,   x_hi 6
//   slip_speed       |v_t| at the contact point [m/s]                  x_ref 1.0,   x_hi 5
//   spin             |omega| of the block [rad/s]                      x_ref 40,    x_hi 100
//   penetration      h [m]                                             x_ref 3e-3,  x_hi 1e-2
//   incidence_angle  theta_in = atan2(-vy, |vx|) of the block centre at contact onset [rad]
//                                                                      x_ref 0.7,   x_hi 1.5
// Bounds: linear c in [-0.9 / x_hi, 3 / x_ref]; power p in [-1.5, 1.5].
// Parameter names: c_<coefficient>_<tag> (linear) or p_<coefficient>_<tag> (power), with the
// variable's short tag vapp, slip, spin, h, theta (e.g. c_muR_spin, p_en2_vapp).
// Why they exist: a constant that drifts with an impact feature is the strongest hint of
// missing physics (Brynjarsdottir & O'Hagan 2014, Inverse Problems 30, 114007): each law is
// that drift written as physics, neutral where it does nothing.
//
// Not covered: coefficients of plugin effects (a plugin's parameters are constants per lane;
// a law would need a factor array that the plugin reads, i.e. a change of ContactBatch).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "effects/effect.hpp"

namespace ricochet::effects {

/// Accepted names, in registry order.
std::span<const std::string_view> law_coefficients();  ///< kn, en2, mu, muR
std::span<const std::string_view> law_variables();     ///< approach_speed, ..., incidence_angle
std::span<const std::string_view> law_forms();         ///< linear, power

/// What a variable is, in law_variables() order.
struct LawVariable {
  std::string_view name;         ///< e.g. "approach_speed"
  std::string_view tag;          ///< short tag in parameter names, e.g. "vapp"
  std::string_view unit;         ///< SI unit of x, e.g. "m/s"
  std::string_view symbol;       ///< in printed laws, e.g. "v0"
  std::string_view description;  ///< one line
  double x_ref;                  ///< reference value of the power form (a typical lab value)
  double x_hi;                   ///< upper end of the lab range (sets the linear lower bound)
};
std::span<const LawVariable> law_variable_info();

/// The configuration of a generated law, e.g. {"muR", "spin", "linear"}.
struct CoefficientLawConfig {
  std::string_view coefficient, variable, form;
};
/// The configuration named by an effect name, or nullopt if the name is not a generated law.
std::optional<CoefficientLawConfig> parse_coefficient_law_name(std::string_view effect_name);

/// "<coefficient>_<variable>_<form>", e.g. "muR_spin_linear" (no check of the parts).
std::string coefficient_law_name(std::string_view coefficient, std::string_view variable,
                                 std::string_view form);
/// The law's parameter name, e.g. "c_muR_spin", "p_en2_vapp". Throws like make_coefficient_law.
std::string coefficient_law_parameter_name(std::string_view coefficient, std::string_view variable,
                                           std::string_view form);

/// One law. Throws std::invalid_argument naming the bad value and listing the accepted ones.
std::unique_ptr<Effect> make_coefficient_law(std::string_view coefficient,
                                             std::string_view variable, std::string_view form);

/// The whole family, coefficients x variables x forms (the registry's order).
std::vector<std::unique_ptr<Effect>> make_coefficient_laws();

/// "generated coefficient laws <coefficient>_<variable>_<form> with coefficient in {...},
/// variable in {...}, form in {...}": for error messages and listings.
std::string coefficient_law_family_text();

}  // namespace ricochet::effects
