// A sphere dropped vertically into a settled bed (liggghts-inputs/drop) and the angle of repose of
// the bed's grains (liggghts-inputs/repose), run through the LIGGGHTS library interface: the
// external check of the resolved bed against granular-impact physics (Uehara et al. 2003,
// Katsuragi & Durian 2007; docs/granular-impact-checks.md, issue 11 item 4).
#pragma once

#include <mpi.h>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bed.hpp"
#include "granular_fits.hpp"
#include "params.hpp"

namespace ricochet::dem {

/// The index variables of liggghts-inputs/drop/setup.in (D_sphere_m, rho_sphere, ...) and of
/// liggghts-inputs/repose/in.repose's own section (L_col_m, ...): the `drop.*` and `repose.*`
/// parameters of `ricochet dem drop --set`. h_drop_m is given per drop, not by --set.
std::vector<DeckParam> drop_deck_params(const Decks& decks);
std::vector<DeckParam> repose_deck_params(const Decks& decks);

/// One drop. The bed is the one of `bed` overrides (its cache key); `seed` = replica: the bed's
/// and the insertion's LIGGGHTS seeds become the (2 seed + 1)-th and (2 seed + 2)-th primes
/// above 10000, as for impacts.
struct DropSpec {
  std::string id;
  double h_drop_m = 0.2;  ///< sphere bottom above the levelled surface at release [m]
  std::optional<std::int64_t> seed;
  std::map<std::string, std::string> bed, block, drop;  ///< overrides by section
};

/// Bed overrides of a drop including its replica seed.
std::map<std::string, std::string> drop_bed_overrides(const DropSpec& spec);

/// The sphere state written by setup.in (one row per record_every steps).
struct DropTrack {
  std::vector<double> t, x, y, depth, vx, vy, vz, fcx, fcy, fcz, ke_grains;
  static const std::vector<std::string>& column_names();  ///< with units, e.g. "depth[m]"
  std::size_t size() const { return t.size(); }
  static DropTrack read(const std::string& path);  ///< ${out}.track.txt
  /// Column `c` (0..10) of the row-major layout of column_names().
  const std::vector<double>& column(std::size_t c) const;
  std::vector<double>& column(std::size_t c);
};

/// How a drop's trajectory is analysed.
struct DropAnalysisOptions {
  std::size_t half_window = 10;  ///< local quadratic derivative half-window [records]
  double stop_fraction = 0.1;    ///< penetration phase ends when z' < this x impact speed
};

struct DropResult {
  std::string id;
  /// at_rest (success) | rebound (bounced off the bed) | timeout | bottom | lost_atoms | nan |
  /// timestep | not_inserted | bed_not_settled | invalid
  std::string status;
  std::string message;
  bool ok() const { return status == "at_rest"; }

  double h_drop_m = 0;
  double D_sphere_m = 0, rho_sphere = 0, mass_kg = 0;
  double rho_bulk = 0;         ///< grain mass over the levelled volume [kg/m^3]
  double depth_final_m = 0;    ///< d of Uehara et al.: bottom of the sphere at rest
  double depth_max_m = 0;      ///< largest depth reached
  double H_total_m = 0;        ///< H = h + d
  double v_impact_mps = 0;     ///< speed when the bottom crosses the levelled surface
  double v_rebound_mps = 0;    ///< largest upward speed after the first contact (0: none)
  double v_contact_mps = 0;    ///< speed at the first contact
  double depth_contact_m = 0;  ///< depth of the bottom at the first contact (< 0: above)
  double t_contact_s = -1;     ///< first contact (force above f_contact_frac x weight)
  double t_penetration_s = 0;  ///< from z = 0 to the end of the fitted phase
  std::size_t kd_samples = 0;  ///< samples of the penetration phase
  /// Katsuragi-Durian on this drop alone: from the depth record (derivatives) and from the
  /// DEM contact force as the acceleration (z'' = g - F_z / m).
  std::optional<KatsuragiDurianFit> kd_trajectory, kd_force;
  DropTrack track;
  std::size_t torn_records = 0;  ///< removed from the track (remove_torn_records)

  std::string bed_key;
  long grains = 0, steps = 0;
  double dt_s = 0, wall_s = 0, cpu_s = 0, sim_time_s = 0;
  std::string work_dir;
};

struct DropContext {
  const Decks* decks = nullptr;
  BedFiles bed;
  std::string work_dir;  ///< this drop's folder (log, screen, track)
  DropAnalysisOptions analysis;
  std::function<void(double, double)> progress;  ///< (simulated time, t_max) after each chunk
};

/// Runs one drop on `comm` (collective). LIGGGHTS-side failures are statuses; results are
/// complete on rank 0 of comm.
DropResult run_drop(const DropSpec& spec, const DropContext& ctx, MPI_Comm comm);

/// Removes the torn records of `track`: those whose velocity differs from the previous kept
/// record's by more than 3 (g + F_max / m) dt, F_max the largest contact force of the track, dt
/// the time between the two. Newton allows at most (g + F_max / m) dt; a record beyond three
/// times that was not written by one step of the run (two writes of the track file interleaved:
/// the h = 0.02 m drop of data/resolved/sphere-drop-1.5e9 holds one, whose vz is an x position).
/// Returns how many were removed.
std::size_t remove_torn_records(DropTrack& track, double mass_kg);

/// Fills the derived quantities of `r` (depths, H, impact speed, per-drop fits) from r.track,
/// after remove_torn_records (their count in r.torn_records).
void analyse_drop(DropResult& r, const DropAnalysisOptions& options);

/// The samples of a drop's penetration phase (depth record, local quadratic derivatives), from
/// the first contact (the first record whose contact force exceeds 5 % of the weight `m g`:
/// coarse grains stand above the mean surface) or, without one, from z = 0.
std::vector<KdSample> drop_samples(const DropTrack& track, const DropAnalysisOptions& options,
                                   double weight_N);

/// The angle of repose of a bed's grains (liggghts-inputs/repose/in.repose).
struct ReposeResult {
  std::string status;  ///< ok | not_settled | failed
  std::string message;
  SlopeFit slope;
  std::vector<double> x_m, h_m;  ///< final surface profile (mean top of the top layer per bin)
  long grains = 0;
  double wall_s = 0;
  std::string work_dir;
};

/// Runs the repose deck with the bed's grain parameters (`bed` overrides; geometry keys of the
/// bed are ignored by the deck) and `repose` overrides in `work_dir`, then fits the heap's flank.
ReposeResult run_repose(const Decks& decks, const std::map<std::string, std::string>& bed,
                        const std::map<std::string, std::string>& repose,
                        const std::string& work_dir, MPI_Comm comm);

}  // namespace ricochet::dem
