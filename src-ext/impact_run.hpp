// One resolved impact: the impact deck (liggghts-inputs/impact/setup.in + check.in) run through
// the library interface, failure detection, and the extraction of V_in and V_out with the lab's
// reconstruction (kinematics::reconstruct, paper section 2.3).
#pragma once

#include <mpi.h>

#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bed.hpp"
#include "common/progress.hpp"
#include "engine/shape.hpp"
#include "impact/block_track.hpp"
#include "impact/impact_set.hpp"
#include "impact/impact_snapshot.hpp"
#include "impact_spec.hpp"
#include "kinematics/reconstruct.hpp"
#include "params.hpp"

namespace ricochet::dem {

/// Bed overrides of a spec including its replica seed (the bed's cache key).
std::map<std::string, std::string> bed_overrides(const ImpactSpec& spec);

/// A run.* (impact deck) parameter of a spec as a number: its override, else the deck's default
/// (impact/setup.in). Throws std::logic_error for a name the deck does not have.
double run_param(const ImpactSpec& spec, const Decks& decks, const std::string& name);

/// Reads the deck's block track ${out}.track.txt (fix print output, impact/setup.in: one record
/// at most `record_dt_s` apart) by the names of its title line ("# t[s] x[m] ..."; without one,
/// the twelve legacy columns, then torque); a column the file does not have is NaN, and so is
/// overlap_d_max, which the driver adds (ricochet::dem::OverlapProbe). theta is unwrapped. A
/// line cut by a crash is skipped. Throws std::runtime_error when the file cannot be read.
BlockTrack read_deck_track(const std::string& path);

struct ImpactResult {
  std::string id;
  /// rebound (success) | no_rebound | timeout | lost_atoms | end_wall | nan | timestep |
  /// not_inserted | invalid | bed_not_settled | extraction_failed | crashed
  std::string status;
  std::string message;  ///< what went wrong, or a summary
  bool ok() const { return status == "rebound"; }

  Impact impact;  ///< the impact-set row (meaningful when ok())
  kinematics::Reconstruction reconstruction;
  /// The block's records (paper frame; its force and torque are the slab block's, whose mass is
  /// block_mass_kg, also stored with the track).
  BlockTrack track;
  double block_mass_kg = std::numeric_limits<double>::quiet_NaN();  ///< the simulated block [kg]
  double force_contact_start_s = -1, force_contact_end_s = -1;      ///< DEM contact-force window
  double penetration_max_m = 0;
  double energy_dissipated_J = 0;     ///< lab-length block: (KE + PE) lost over the contact
  double energy_dissipated_frac = 0;  ///< over the block's kinetic energy at first contact
  double crater_depth_m = 0, crater_width_m = 0;
  Vel3 v_start_direct{}, v_end_direct{};  ///< block velocity at the force-window ends

  std::string bed_key;
  /// Effective grain-scale parameters of this impact: the bed's (from its .params file) and the
  /// grain-block contact's (deck defaults with the spec's overrides), recorded with the result.
  std::map<std::string, std::string> bed_values, block_values;
  long grains = 0, steps = 0, block_spheres = 0;
  long grains_lost = 0;  ///< grains thrown out of the box (tolerated up to grains / 100)
  double dt_s = 0, wall_s = 0, sim_time_s = 0;
  double cpu_s = 0;  ///< CPU time of the LIGGGHTS run, summed over the instance's ranks
  /// Resumed from a checkpoint at this simulated time [s] (impact_checkpoint.hpp); -1: ran whole.
  /// wall_s and cpu_s then include the earlier segments.
  double resumed_from_s = -1;
  double rayleigh_fraction = 0, hertz_fraction = 0;  ///< from fix check/timestep/gran
  std::string work_dir;
  /// The impact picture, when ImpactContext::snapshot asked for it (stored by append_result).
  std::optional<ImpactSnapshot> snapshot;
};

/// Everything run_impact needs besides the spec.
/// Default steps between ParaView frames (`--vtk-every`): about 5 ms of simulated time on the
/// default bed (dt 22 us), ten frames through a cylinder's contact.
inline constexpr long kDefaultVtkEvery = 250;

struct ImpactContext {
  const Decks* decks = nullptr;
  BedFiles bed;
  std::string template_include;  ///< from ensure_template
  std::string work_dir;          ///< this impact's folder (log, screen, track)
  ExtractOptions extract;
  /// ParaView output (docs/paraview.md): when vtk_every > 0, the deck dumps the grains and the
  /// block's spheres every vtk_every steps into vtk_dir (created) as grains_<step>.vtk and
  /// block_<step>.vtk.
  std::string vtk_dir;
  long vtk_every = 0;
  /// When not empty: the deck also dumps text frames every kDefaultVtkEvery steps into this
  /// folder (created), cut into the impact picture (ImpactResult::snapshot), then removed.
  std::string picture_dir;
  /// Called after every chunk with (simulated time, t_max) on every rank.
  std::function<void(double, double)> progress;
};

/// Generates (once) the multisphere template of `shape` for `bed` (slab: the slab width; box: the
/// block's length) in `dir`; returns the LIGGGHTS include file. Deterministic content, written to
/// a temporary name and renamed, so concurrent callers are safe.
std::string ensure_template(const Shape& shape, const BedFiles& bed, const std::string& dir);
/// The same on every rank of `comm` (collective): rank 0 writes the template first, the others
/// find it after a barrier.
std::string ensure_template(const Shape& shape, const BedFiles& bed, const std::string& dir,
                            MPI_Comm comm);

/// A progress bar over one impact's simulated time, drawn where `shown` (one rank, and not under
/// --json): callback() is ImpactContext::progress. `dem impact` and `dem campaign` share it.
class ImpactProgress {
 public:
  ImpactProgress(const std::string& id, bool shown);
  ~ImpactProgress();
  ImpactProgress(const ImpactProgress&) = delete;
  ImpactProgress& operator=(const ImpactProgress&) = delete;
  /// The callback; valid while this object lives.
  std::function<void(double, double)> callback();
  void finish();

 private:
  std::unique_ptr<Progress> bar_;
  std::size_t shown_ = 0;
};

/// Checks what would make LIGGGHTS stop with an error or give a meaningless impact (incident
/// vy >= 0, insertion outside the box, contact too close to an end wall). Returns an empty
/// string when the set-up is valid, else the reason.
std::string validate_setup(const ImpactSpec& spec, const Shape& shape, const Decks& decks,
                           const BedFiles& bed);

/// Runs one impact on `comm` (collective). Never throws for a LIGGGHTS-side failure: the status
/// says what happened. Results are complete on rank 0 of comm.
ImpactResult run_impact(const ImpactSpec& spec, const ImpactContext& ctx, MPI_Comm comm);

/// The atoms an impact may have lost and still count (the deck's check.in applies the same rule):
/// a few grains thrown out of the box by the block (the triangles' vertices splash them over the
/// top) do not change its motion; a lost block sphere, or more than a hundredth of the bed's
/// `bed_grains`, ends the run. `atoms` and `grains` are the instance's counts now. Returns the
/// grains lost (>= 0) when the loss is acceptable, -1 when it is not.
long acceptable_grain_loss(long atoms, long grains, long bed_grains, long block_spheres);
/// Whether the block was inserted: a fresh impact has every atom (`atoms` == bed_grains +
/// block_spheres); a resumed one (`resumed`) lacks the grains its checkpoint had lost already,
/// which acceptable_grain_loss judges (2026-12-06: T01 of the blind triangles had lost 327 grains
/// by its checkpoint and was recorded not_inserted on resuming).
bool block_inserted(long atoms, long grains, long bed_grains, long block_spheres, bool resumed);

/// Names and SI units of the extra impact-set columns of a resolved impact (Impact::extra):
/// energy_dissipated_frac [-], crater_depth [m], crater_width [m], the block velocity at the
/// ends of the contact-force window (vin_x_direct ... wout_direct) and force_contact_duration [s].
const std::vector<std::string>& impact_extra_names();
const std::vector<std::string>& impact_extra_units();

/// Surface height profile of the grains along x (mean top of the top layer per bin) [m];
/// collective over comm. Used for the crater.
std::vector<double> surface_profile(class Liggghts& lmp, const BedFiles& bed, double bin_m);

}  // namespace ricochet::dem
