// The reduced law's contact force along a prescribed path (issue 33, item 2): the block is moved
// through measured states (a LIGGGHTS track, an independent simulator's trace, a tracked video)
// instead of being integrated, and the model's effects are evaluated at every state, with their
// per-contact history carried from state to state as the engine carries it from step to step.
// The measured force minus this one is the residual the force-law discovery explains
// (diagnosis/force_law.hpp).
//
// Frames and units: the engine's (engine.hpp): paper frame, x along the flight, y up, angles and
// spins counter-clockwise, the ground of EngineOptions::ground (flat y = 0 by default), SI units.
// The contact geometry is the engine's (detail::vertex_contact: penetration h = r - distance of
// the vertex to the ground, contact point midway in the overlap) and so is the order in which the
// effects act (effect.hpp, Stage).
#pragma once

#include <span>
#include <vector>

#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"

namespace ricochet {

/// One state of the block along the path [s, m, rad, m/s, rad/s].
struct PathState {
  double t_s = 0;
  double x_m = 0, y_m = 0, theta_rad = 0;
  double vx_mps = 0, vy_mps = 0, w_radps = 0;
};

/// The law's action on the block at one state, and the contact it read.
struct PathForce {
  /// Total force on the block, contact and body stages [N] (ground frame), and the torque about
  /// the centre of mass [N m] (counter-clockwise > 0).
  double fx_N = 0, fy_N = 0, torque_Nm = 0;
  /// The deepest contact slot: penetration [m], the normal and tangential velocities of its
  /// contact point [m/s], its lever (contact point to centre of mass) [m] and that point
  /// relative to the centre (rcx, rcy) [m], its unit normal, and whether its penetration grew
  /// since the previous state. h = 0 and the rest 0: no contact. h is the overlap with the
  /// surface the block touches, which an effect that heaps sand raises (Effect::moves_surface).
  double h_m = 0, vn_mps = 0, vt_mps = 0, lever_m = 0, rcx_m = 0, rcy_m = 0, nx = 0, ny = 1;
  bool loading = false;
  /// Its normal and tangential force [N] and rolling moment [N m] (the slot's own, effect.hpp).
  double fn_N = 0, ft_N = 0, moment_Nm = 0;
};

/// Evaluates `model` with parameter values `params` (model order, empty = model.values()) along
/// `path` (states in increasing time; the first is taken out of contact or at the start of the
/// contact: history before it is zero), one PathForce per state. Between two states the block
/// follows the cubic Hermite curve through their positions and velocities, in sub-steps of at
/// most options.dt_s, so that the incremental laws see the turn from loading to unloading where
/// it happens and the springs integrate the slip at the engine's resolution (path_force.cpp).
/// Uses options.dt_s and options.ground. Throws InputError (file "<path>", the state's index
/// from 1 as the line) for a non-finite state or a time that does not increase, and
/// std::out_of_range for parameters out of bounds (Model::check).
std::vector<PathForce> law_force_along(const Model& model, const Shape& shape,
                                       std::span<const PathState> path,
                                       std::span<const double> params = {},
                                       const EngineOptions& options = {});

}  // namespace ricochet
