// What the tracks of a resolved campaign say about its contacts (issue 32, item 4): per impact,
// the records and their spacing, the contact window from the force, the peak force and torque,
// the depth and its elastic recovery, the largest grain overlap, the impact proper (until the
// force falls to the block's weight) and the speed it gives back; over the impacts, their summary.
// `ricochet stats` prints it for a file that keeps tracks (docs/commands/stats.md, "Tracks").
#pragma once

#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "impact/block_track.hpp"
#include "impact/impact_set.hpp"
#include "stats/stats.hpp"

namespace ricochet::stats {

/// One impact's track in numbers, SI units; NaN where the track cannot say (no contact force,
/// a column the file lacks, fewer than two records).
struct TrackSummary {
  std::string id;
  std::size_t records = 0;
  /// Largest time between consecutive records [s]: the resolution of every time below.
  double max_interval_s = std::numeric_limits<double>::quiet_NaN();
  /// Contact window from the force: the run of consecutive records around the largest contact
  /// force |(fcx, fcy)| in which it exceeds 0.2 of the block's weight (the impact deck's contact
  /// criterion, f_contact_frac) [s], and its length [s]; without a block mass, any nonzero force.
  /// It is the contact phase that carries the peak: a block that leaves the bed and lands again
  /// has a second phase, outside it. The driver's force window (index force_contact_start_s,
  /// _end_s; /impacts force_contact_duration) takes the first and last records above the same
  /// criterion up to the deck's separation, with the block at most two grain radii above the
  /// surface: it spans such phases and can be longer. first_touch_s and last_touch_s are the
  /// first and last nonzero force of the whole track, with the grains that still touch the block
  /// in flight after the rebound.
  double contact_start_s = std::numeric_limits<double>::quiet_NaN();
  double contact_end_s = std::numeric_limits<double>::quiet_NaN();
  double contact_duration_s = std::numeric_limits<double>::quiet_NaN();
  double first_touch_s = std::numeric_limits<double>::quiet_NaN();
  double last_touch_s = std::numeric_limits<double>::quiet_NaN();
  double peak_normal_force_N = std::numeric_limits<double>::quiet_NaN();      ///< max fcy
  double peak_tangential_force_N = std::numeric_limits<double>::quiet_NaN();  ///< max |fcx|
  double peak_torque_Nm = std::numeric_limits<double>::quiet_NaN();           ///< max |torque|
  double max_penetration_m = std::numeric_limits<double>::quiet_NaN();
  /// Penetration at the end of the contact window [m], and the elastic recovery, max minus it
  /// [m]: how much of the deepest depth the bed gives back before the block leaves (issue 32,
  /// item 1: "largest minus final depth").
  double final_penetration_m = std::numeric_limits<double>::quiet_NaN();
  double elastic_recovery_m = std::numeric_limits<double>::quiet_NaN();
  double max_overlap_d = std::numeric_limits<double>::quiet_NaN();  ///< max overlap_d_max [-]
  /// The share of the contact window's upward impulse, sum of max(fcy, 0) dt over its records (dt:
  /// to the next record), taken while the penetration is negative: the block's lowest point above
  /// the levelled surface, pushed by grains heaped above it (the rim of a crater) [-]. 0 on a bed
  /// that only pushes from below the surface; NaN without a window or a penetration column.
  double lift_above_surface = std::numeric_limits<double>::quiet_NaN();
  /// The impact proper: from the contact window's start to the first record after the largest
  /// force at which the contact force no longer exceeds the block's weight m g, i.e. the bed no
  /// longer decelerates the block more than it carries it [s]; the block's vertical velocity
  /// there [m/s]; and the impact's own restitution, that velocity over minus the one at the
  /// window's start [-]. NaN without a block mass or without such a record. What follows within
  /// the contact window is the block carried by a force of about its weight: a cylinder rolling
  /// out of its crater over the rim it pushed up (the sand-calibrated grains at 1.5e9 Pa,
  /// docs/resolved-model.md) gains there the upward speed the impact did not give back.
  double impact_duration_s = std::numeric_limits<double>::quiet_NaN();
  double vy_impact_end_mps = std::numeric_limits<double>::quiet_NaN();
  double impact_restitution = std::numeric_limits<double>::quiet_NaN();
  /// How long the bed keeps pressing after the impact: from the largest force's record to the
  /// last record of the unbroken run after it whose force, averaged over the records within 1
  /// ms either side, stays above twice the block's weight [s] (0 when the next record's is
  /// already at most 2 m g; NaN without a block mass or a window). A bed that springs back as
  /// a whole carries the block on a force of several weights for tens of ms after the peak (the
  /// cylinder at 1.5e10 Pa on soft walls, liggghts-inputs/campaigns/wall-stiffness-1.5e10.toml:
  /// its "second phase" is this above 20 ms).
  double above_two_weights_after_peak_s = std::numeric_limits<double>::quiet_NaN();
  /// The simulated block's mass [kg] (its forces are its own: a slab carries the fraction slab
  /// width / block length of the lab block): the track's when the file keeps it ("file"), else
  /// free_flight_mass_kg ("free flight"), else NaN ("unknown").
  double block_mass_kg = std::numeric_limits<double>::quiet_NaN();
  std::string block_mass_source = "unknown";
};

/// The simulated block's mass [kg] from the track's free flight before the first touch: there
/// the kinetic energy grows by the work of gravity on the translation only (no contact, so no
/// torque and a constant spin), Delta ke_block = m/2 Delta(vx^2 + vy^2), taken between the first
/// and the last free-flight record. NaN with fewer than two such records.
double free_flight_mass_kg(const BlockTrack& track);

/// The numbers of one track (NaN values of a column are skipped).
TrackSummary summarize_track(const BlockTrack& track, const std::string& id);

/// A contact window by TrackSummary::contact_start_s's rule, as record indices: `peak` the
/// record of the largest force |(fx, fy)| [N] that bears, `first` and `last` the ends of the run
/// of consecutive bearing records around it. A record bears when its force exceeds 0.2 of the
/// weight of a block of `mass_kg` [kg] (the impact deck's contact criterion; without a mass, NaN:
/// any force above rounding of the largest) and, where standard errors `sigma_fx`, `sigma_fy`
/// [N] are given (forces from tracked accelerations), twice their hypot. nullopt when none bears.
/// The force-history floor aligns replicate histories at `first` (diagnosis/force_history.hpp).
struct ContactWindow {
  std::size_t first = 0, peak = 0, last = 0;
};
std::optional<ContactWindow> contact_window(std::span<const double> fx, std::span<const double> fy,
                                            double mass_kg, std::span<const double> sigma_fx = {},
                                            std::span<const double> sigma_fy = {});

/// One quantity of TrackSummary: its JSON key, unit, text label and the scale to print it in.
struct TrackQuantity {
  const char* key;
  const char* unit;
  const char* label;  ///< with the printed unit
  double print_scale;
  double TrackSummary::*member;
};
/// The quantities summarised over impacts, in print order.
const std::vector<TrackQuantity>& track_quantities();

/// The tracks of a file's releases.
struct TrackTable {
  std::string source;                 ///< the file
  std::vector<TrackSummary> impacts;  ///< releases of the set with a track, in set order
  std::size_t releases = 0;           ///< releases of the set
  std::size_t other_tracks = 0;       ///< tracks of impacts not in the set (failed, filtered)
  std::vector<Summary> over_impacts;  ///< per track_quantities(), over `impacts`
};

/// Reads the track of every release of `set` that `path` keeps (impact/block_track.hpp) and
/// summarises them; an empty table when the file keeps none. Throws InputError (file, track)
/// for a malformed track.
TrackTable track_table(const std::string& path, const ImpactSet& set);

/// JSON: "group", "releases", "with_track", "other_tracks", "summary" {key: {n, mean, std,
/// min, max, unit}} over track_quantities(), "impacts" [{id, records, contact_start,
/// contact_end, first_touch, last_touch, block_mass_source, every quantity}], SI units, NaN as
/// null.
nlohmann::json to_json(const TrackTable& table);
/// The summary over impacts as `ricochet stats` prints it.
std::string format_text(const TrackTable& table);

}  // namespace ricochet::stats
