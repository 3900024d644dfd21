// Invariants every effect must satisfy, checkable in one line by the author of a new effect:
//
//   for (auto& problem : ricochet::check_effect_invariants(my_effect)) std::cerr << problem;
//
// The project's own test suite runs it over the whole registry (tests/engine/effect_invariants).
#pragma once

#include <string>
#include <vector>

#include "effects/effect.hpp"

namespace ricochet {

/// Returns the violated invariants, empty when the effect is sound:
///  1. declared parameters have lower <= nominal <= upper, neutral within bounds or NaN,
///     non-empty names and units;
///  2. out of contact (active = 0) it adds no force or moment, raises no surface, and leaves its
///     state at zero;
///  3. it writes only the outputs of its stage (coefficient effects: the factors only; normal:
///     fn; tangential: ft; rolling: moment; body: fx_body, fy_body), and the surface
///     (lift_next) only if it declares moves_surface();
///  4. outputs and state stay finite with every parameter at its lower, nominal and upper bound,
///     over a grid of penetrations, velocities and spins;
///  5. added to the paper's law, it never creates energy: over a collision of the lab cylinder and
///     triangle, kinetic energy out + potential energy gained <= kinetic energy in, with its
///     parameters at the lower, nominal and upper bounds (runs the real engine);
///  6. at its neutral values (when every parameter has one), the paper's law is unchanged.
std::vector<std::string> check_effect_invariants(const Effect& effect);

}  // namespace ricochet
