// Extraction of an impact's result from what its LIGGGHTS run left (impact_run.cpp runs it and
// calls these in order): the deck's track, the status's message, the DEM contact-force window,
// the crater, and V_in / V_out by the lab's reconstruction (paper section 2.3) on camera-like
// frames. Internal to ricochet_dem.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/shape.hpp"
#include "impact_run.hpp"

namespace ricochet::dem {

/// What the LIGGGHTS run leaves beside the result's fields.
struct Simulated {
  std::vector<double> before, after;  ///< surface profiles before and after (crater)
  double block_mass = 0, t_max = 0, deck_contact_end = -1;
  std::vector<std::pair<double, double>> overlaps;  ///< (t, largest grain overlap / d)
  /// A resumed run (impact_checkpoint.hpp): the impact's time at its checkpoint [s] (else -1),
  /// and the wall and CPU seconds its earlier segments spent.
  double resumed_from_s = -1, earlier_wall_s = 0, earlier_cpu_s = 0;
};

/// The deck's track file `out`.track.txt into r.track, with the overlap samples joined by time
/// (they are taken at the track's steps). False when it cannot be read (the status says why).
bool read_track(ImpactResult& r, const std::string& out,
                const std::vector<std::pair<double, double>>& overlaps);

/// The messages of the statuses the deck and the driver end a run with.
void explain_status(ImpactResult& r, double t_max);

/// DEM contact-force window: the deck's criterion (check.in) at full record resolution, from the
/// first touch to the last touch before the deck's own separation time (check.in samples chunk
/// ends; later touches are grains thrown up with the block, whose impulses are negligible). The
/// velocities at its ends and the energy lost over it into r; the window's record indices, or
/// nullopt (status set) without a contact force.
std::optional<std::pair<std::size_t, std::size_t>> force_window(ImpactResult& r,
                                                                const ImpactSpec& spec,
                                                                const ImpactContext& ctx,
                                                                const Shape& shape,
                                                                const Simulated& sim);

/// Crater: largest drop of the surface profile under the block's path during the contact
/// (records i0..i1), and the width of the contiguous bins around it that dropped by more than a
/// grain radius [m].
void measure_crater(ImpactResult& r, const Simulated& sim, const Shape& shape, double r_max_m,
                    double crater_bin, std::size_t i0, std::size_t i1);

/// V_in and V_out with the lab's reconstruction on camera-like frames, and the release in the
/// impact-set schema. False (status set) when it fails or is not a rebound.
bool extract_release(ImpactResult& r, const ImpactSpec& spec, const ImpactContext& ctx,
                     const Shape& shape);

}  // namespace ricochet::dem
