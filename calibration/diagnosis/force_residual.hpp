// The residual contact force of measured histories (issue 33, item 2): a release's measured force
// and torque minus the reduced law's along the release's own measured path
// (engine/path_force.hpp), in the contact frame, ready for the force-law discovery
// (diagnosis/force_law.hpp). The histories are the impact-set schema's tracks
// (impact/block_track.hpp): a LIGGGHTS campaign's, an independent simulator's, a tracked video's.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "diagnosis/force_law.hpp"
#include "diagnosis/residual_map.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/path_force.hpp"
#include "engine/shape.hpp"
#include "impact/block_track.hpp"
#include "impact/impact_set.hpp"
#include "stats/sparse_regression.hpp"

namespace ricochet::diagnosis {

/// One release's measured contact history in the reduced engine's frame and units: the path
/// (PathState, y above the levelled surface) and the contact force and torque on the lab block
/// (fx, fy [N], torque about the centre of mass [N m]; NaN where not measured).
struct MeasuredHistory {
  std::string id;
  /// The file the history was read from ("" when made in memory): force_residual names it and
  /// the track in the InputError of a path it cannot follow.
  std::string source;
  std::vector<PathState> path;
  std::vector<double> fx_N, fy_N, torque_Nm;
  /// The force scale applied to the track's forces (lab mass / simulated mass; 1 when the
  /// track's block is the lab block), and the levelled surface's height in the track's frame [m].
  double force_scale = 1, surface_m = 0;
  /// The largest |h_shape - penetration| over the records in contact [m]: the shape's deepest
  /// overlap on the path against the track's own penetration column. Large when the track's
  /// block is not `shape` or its angle is not the engine's.
  double geometry_mismatch_m = 0;
};

/// The history of `track` for `shape`: the forces scaled by shape.mass_kg / the simulated
/// block's mass (the track's block_mass_kg, else its free-flight estimate,
/// stats::free_flight_mass_kg; unscaled when neither is known), the surface height the median of
/// y - depth_below_centroid(theta) + penetration over the records with a penetration, and y
/// taken above it. The track's theta is taken as the engine's orientation. Throws InputError
/// (file `source`, field "/dem/tracks/ID") for a track of fewer than two records or without a
/// finite contact force; the path itself is checked by force_residual (law_force_along).
MeasuredHistory measured_history(const BlockTrack& track, const std::string& id, const Shape& shape,
                                 const std::string& source);

/// The histories `data` keeps (block_track_ids, read by measured_history) of the releases of
/// `set`, aligned with set.impacts (nullopt for a release without one). Empty histories (none
/// kept: a CSV set, a campaign without tracks) give all nullopt. Throws InputError for a
/// malformed track, naming the file and the track.
std::vector<std::optional<MeasuredHistory>> measured_histories(const std::string& data,
                                                               const ImpactSet& set,
                                                               const Shape& shape);

/// The number of releases with a history.
std::size_t history_count(const std::vector<std::optional<MeasuredHistory>>& histories);

/// The residual of one history against `model` at `params` (model order; empty = its values):
/// the samples where the law's deepest slot is in contact (h > 0), with that slot's state
/// (ContactSample) and, in its contact frame (n, t = (n_y, -n_x)), the residual normal and
/// tangential force [N] and the residual moment about the contact point [N m] (the torque
/// residual minus the moment of the force residual at the contact point). A path law_force_along
/// refuses (a non-finite state, a time that does not increase) is an InputError naming
/// history.source, "/dem/tracks/ID" and the record.
ReleaseResidual force_residual(const MeasuredHistory& history, const Model& model,
                               const Shape& shape, std::span<const double> params = {},
                               const EngineOptions& engine = {});

/// Sums of squared residuals and sample counts per component (force_residual's rows; a NaN
/// component, not measured, is skipped): the force-history error pools them over releases and
/// splits, the history objective over the releases being fitted.
struct ResidualSquares {
  std::array<double, kForceComponents> sum{};
  std::array<std::size_t, kForceComponents> n{};
  void add(const ReleaseResidual& r);
  void add(const ResidualSquares& other);
  /// Per component sqrt(sum / n); NaN where n = 0.
  std::array<double, kForceComponents> rms() const;
};

/// The force law missing from a model, discovered from the histories a file keeps.
struct ForceLawReport {
  std::vector<std::string> ids;                     ///< the releases with a history, in set order
  std::size_t samples = 0;                          ///< contact samples analysed (the law's h > 0)
  double force_scale_min = 1, force_scale_max = 1;  ///< the forces' scale (measured_history)
  double geometry_mismatch_m = 0;  ///< the largest over the releases (measured_history)
  /// The law the residual was taken against: "per-release fits" (each release at its own
  /// calibration, so that the constants' release-to-release scatter is not read as a force) or
  /// "population fit".
  std::string base;
  std::vector<ComponentLaw> laws;  ///< discover_force_law's
  /// The residual against the base law by branch and depth (residual_map): where the law fails,
  /// whatever the library names.
  ResidualMap map;
  /// The terms the law was limited to (discover_force_law's `named`), empty when they were
  /// selected: the law was then fitted, not discovered.
  std::vector<std::string> named;
  /// Wall time [s] of the residuals along the paths and the discovery (selection, bootstrap);
  /// force_law_from_tracks adds the reading of the tracks.
  double seconds = 0;
};

/// The histories `data` keeps (block_track_ids) of the releases of `set`, against `model` at
/// `params` (model order; the caller's calibration, e.g. the diagnosis's population fit), through
/// force_residual and discover_force_law. `release_params`, when not empty, is aligned with
/// set.impacts: each release's own calibration (the diagnosis's per-release fits), used for its
/// history instead of `params` where its entry is not empty. nullopt when `data` keeps fewer
/// than two histories of the set's releases (a CSV set, a campaign without tracks). Throws
/// InputError for a malformed track, naming the file and the track.
std::optional<ForceLawReport> force_law_from_tracks(
    const std::string& data, const ImpactSet& set, const Shape& shape, const Model& model,
    std::span<const double> params, const EngineOptions& engine = {},
    const stats::SparseOptions& options = {},
    const std::vector<std::vector<double>>& release_params = {});

/// The same from histories already read (measured_histories), aligned with `release_params`
/// when that is not empty: a caller that discovers on several subsets of one set (the ladder's
/// leak-free rung, one discovery per split) reads the tracks once. `named`: fit these terms
/// instead of selecting (discover_force_law).
std::optional<ForceLawReport> force_law_from_histories(
    const std::vector<std::optional<MeasuredHistory>>& histories, const Shape& shape,
    const Model& model, std::span<const double> params, const EngineOptions& engine = {},
    const stats::SparseOptions& options = {},
    const std::vector<std::vector<double>>& release_params = {},
    std::span<const ForceTerm* const> named = {});

/// JSON: ids, samples, force_scale [min, max], geometry_mismatch_m, seconds, named (the terms of
/// a named law, [] for a discovered one), and per component its
/// law: component, text, releases, samples, rms_residual, heldout_rms, and the selected terms
/// (name, expression, unit, literature, coefficient, lo, hi, inclusion).
nlohmann::json to_json(const ForceLawReport& report);
/// The laws found, in words: the text of every component with a selected term, joined by "; "
/// (empty when nothing was found).
std::string found_law_text(const ForceLawReport& report);
/// The report in words: one line per component (ComponentLaw::text) and what it rests on.
std::string format_text(const ForceLawReport& report);

}  // namespace ricochet::diagnosis
