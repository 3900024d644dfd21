// One resolved impact beside the reduced law (issue 32, item 4): the contact force and the
// penetration against time from the LIGGGHTS track (impact/block_track.hpp) and from the engine's
// trace (engine/engine.hpp, Trace) of the same incident state, for the report's section of a
// resolved campaign (`ricochet report`, diagnosis/validation_report.cpp).
#pragma once

#include <optional>
#include <span>
#include <string>

#include "diagnosis/figures.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::diagnosis {

/// Three panels against the time since the start of the contact [ms], each with the LIGGGHTS
/// curve and the reduced law's: the normal contact force (LIGGGHTS fcy, the engine's fn) [N],
/// the tangential one (fcx, ft) [N], both in the paper frame on a horizontal bed surface, and
/// the penetration (the block's lowest point below the levelled surface; the engine's deepest
/// vertex overlap h) [mm].
///
/// The impact: `preferred_id` (the one the campaign's picture shows) when `data` keeps its
/// track and `set` has it, else the first release of `set` whose track `data` keeps. The
/// reduced law: `model` at `params` (model order; empty = its values), simulated from that
/// release's V_in and alpha_in (0 when absent) with `engine`.
///
/// LIGGGHTS forces are the simulated block's: a slab of width w carries the fraction w / L of
/// the lab block, so they are scaled by shape.mass_kg / the slab block's mass (the track's
/// block_mass_kg, else its free-flight estimate, stats/track_summary.hpp) to the lab block the
/// engine simulates; the caption says which, and leaves them unscaled when the mass is unknown.
/// Time zero: LIGGGHTS, the start of the contact window (stats::summarize_track); the engine,
/// its first step with a contact force.
///
/// nullopt when `data` keeps no track of a release of `set`. Throws InputError for a malformed
/// track, and what simulate throws (e.g. a time step above the model's stability limit).
std::optional<NamedFigure> contact_track_figure(const std::string& data, const ImpactSet& set,
                                                const Shape& shape, const Model& model,
                                                std::span<const double> params,
                                                const EngineOptions& engine,
                                                const std::string& preferred_id,
                                                const std::string& title);

}  // namespace ricochet::diagnosis
