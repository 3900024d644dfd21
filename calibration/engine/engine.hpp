// The reduced contact-law engine: one rigid 2-D sphero-polygon block colliding with the ground
// (Garcia et al. 2020, section 4.1, Fig. 14), with the contact law given by a Model (a
// composition of effects).
//
// Integration: velocity Verlet (paper section 4.1; Verlet 1967) as in Rockable: positions with
// the previous accelerations, forces at the half-step velocities, then velocities completed.
// Contacts: each polygon vertex dilated by the rounding radius is one contact slot with its own
// history; penetration h = r - (distance of the vertex to the ground); contact point midway in
// the overlap; lever arm l = |contact point - centre of mass| (paper Eq. 6).
//
// Initial state (paper Fig. 14): block rotated by alpha_in, lowest point `initial_gap_m` above
// the ground at x = 0, velocities V_in.
// End of rebound (objective): the reflected velocity is the state at the FINAL separation, i.e.
// the first step with no contact slot in overlap, the centre moving up (vy > 0) and no vertex
// predicted to touch the ground again during the ballistic flight up to the apex (exact
// parabolic flight with constant spin, sampled at <= 2 degrees of rotation). If a re-contact is
// predicted, the block is advanced ballistically to just before it and the rebound continues
// (contact_phases counts the phases). No free flight is simulated after the final separation.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/option_problems.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"

namespace ricochet {

struct EngineOptions {
  double dt_s = 1e-5;          ///< time step [s]; must resolve sqrt(I/kr) (1.3e-4 s / 2 pi)
  double max_time_s = 0.5;     ///< a rebound not over by then ends with kNoRebound
  double gravity_mps2 = 9.81;  ///< gravitational acceleration [m/s^2]
  double initial_gap_m = 0.0;  ///< lowest point above the ground at t = 0 [m]
  Ground ground;               ///< flat y = 0 by default
  /// Flights of a polygon on flat ground between contact phases (and before its first contact)
  /// are jumped ballistically, by whole steps, while no vertex can reach the ground: the result
  /// is stepping's up to rounding (1e-9 m/s over 6,000 random triangle collisions, test
  /// Engine.FlightSkipIsSteppingUpToRounding). false steps through them.
  bool skip_flights = true;
  std::size_t lanes = 64;  ///< collisions integrated together (SoA width)
  int threads = 0;         ///< OpenMP threads for batches, 0 = default

  /// The allowed ranges (problems(); the command line shows kDt in --help). dt_s: below 1e-3 s,
  /// a lab contact (5-20 ms) still spans 5 steps or more; the model's own stability limit
  /// depends on its parameters and is checked against them by simulate and simulate_batch
  /// (critical_time_step). max_time_s: 100 s is 1e7 steps at the default step, thousands of
  /// times the longest lab contact, and bounds the cost of a rebound that never ends.
  static constexpr OptionRange kDt{0, 1e-3, true, true};
  static constexpr OptionRange kMaxTime{0, 100, true, false};
  /// threads: 0 (OpenMP's default) to 4096, far above any node's cores; lanes: 1 to 4096 (a
  /// wider block only costs memory, 64 fills a 512-bit vector eight times).
  static constexpr OptionRange kThreads{0, 4096, false, false};
  static constexpr OptionRange kLanes{1, 4096, false, false};
  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// simulate and simulate_batch call it at their entry.
  OptionProblems problems() const;
};

/// The engine settings of the bulk runs on lab-scale collisions (calibration, Monte Carlo, Sobol,
/// synthetic truths): EngineOptions with max_time_s = 0.1 s. Deliberately shorter than
/// EngineOptions' 0.5 s: lab contacts last 5-20 ms, so 0.1 s is five times the longest, and a
/// case that never leaves the ground (a failed rebound, scored as such) costs a fifth as much;
/// a single `simulate` keeps 0.5 s, since there a long contact is what one looks at.
inline EngineOptions bulk_engine_options() {
  EngineOptions e;
  e.max_time_s = 0.1;
  return e;
}

/// One collision to simulate.
struct CollisionCase {
  Vel3 vin{};              ///< incident (vx [m/s], vy [m/s], omega [rad/s]), vy < 0
  double alpha_rad = 0.0;  ///< incidence angle: block orientation at t = 0 [rad]
};

enum class CollisionStatus : int {
  kOk = 0,         ///< rebound ended by final separation
  kNoRebound = 1,  ///< still in contact (or not leaving) at max_time_s
  kNoContact = 2,  ///< never touched the ground before max_time_s
};
const char* status_name(CollisionStatus status);

struct CollisionResult {
  Vel3 vout{};                    ///< state at final separation (m/s, m/s, rad/s)
  double contact_duration_s = 0;  ///< first touch to final separation
  double max_penetration_m =
      0;  ///< largest overlap h over all slots, below the undisturbed ground (a surface an effect
          ///< heaps up, Effect::moves_surface, is not counted)
  /// Work done BY each stage's forces on the block over the collision, negated: energy
  /// dissipated [J] per Stage (coefficient stage is always 0). Springs' stored energy left at
  /// separation counts as dissipated (paper Fig. 13 gray areas).
  std::array<double, kStageCount> dissipated_J{};
  double kinetic_in_J = 0, kinetic_out_J = 0;  ///< translational + rotational kinetic energy
  double potential_change_J = 0;               ///< m g (y_out - y_in)
  int contact_phases = 0;                      ///< contact intervals within the rebound
  CollisionStatus status = CollisionStatus::kOk;
  double end_time_s = 0;
  double alpha_out_rad = 0;  ///< orientation at separation
};

/// Time history of one collision (for figures and tests).
struct Trace {
  std::vector<double> t, x, y, theta, vx, vy, w, fn, ft, moment, h;
};

/// Stability limit of the explicit integration [s]: 2 / omega_max over the model's springs, found
/// by their declared roles (ParameterRole): normal and tangential stiffnesses on the smallest
/// effective mass of a contact point, 1 / (1/m + R_b^2 / I), rolling stiffnesses on I. A normal
/// stiffness counts with the product of the effects' max_stiffness_factor() at a penetration up
/// to the bounding radius R_b (hertz_stiffness, a generated law of kn). `params`: the model's
/// full parameter vector. A model without springs has no limit (infinity). simulate() refuses a
/// larger dt.
double critical_time_step(const Model& model, const Shape& shape, std::span<const double> params);

/// Runs one collision with parameter values `params` (model order; empty = model.values()).
/// Options with problems (EngineOptions::problems) are refused with InputError before any step;
/// simulate_batch does the same.
CollisionResult simulate(const Model& model, const Shape& shape, const CollisionCase& collision,
                         std::span<const double> params = {}, const EngineOptions& options = {},
                         Trace* trace = nullptr);

/// Runs many collisions in one call, parallel over cores (OpenMP) and vectorised over lanes.
/// `params` holds either model.parameter_count() values (shared by all cases) or
/// cases.size() * parameter_count() values (row per case); empty = model.values().
/// Deterministic: a case's result does not depend on the batch, the lane or the thread count.
std::vector<CollisionResult> simulate_batch(const Model& model, const Shape& shape,
                                            std::span<const CollisionCase> cases,
                                            std::span<const double> params = {},
                                            const EngineOptions& options = {});

/// Collisions simulated by this process so far, by simulate and simulate_batch on every thread:
/// the unit of the benchmarks' cost accounts (benchmarks/bench_diagnosis.cpp).
std::uint64_t collisions_simulated();

}  // namespace ricochet
