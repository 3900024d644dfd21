// Settled beds: built once with liggghts-inputs/bed/in.bed and cached by the hash of their
// parameters (bed_key), so every impact on the same bed, in this run or a later one, reuses it.
#pragma once

#include <mpi.h>

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "params.hpp"

namespace ricochet::dem {

/// A bed on disk: PREFIX.restart (the grains) and PREFIX.params (the parameters it was made with,
/// written by in.bed and read back by the impact deck).
struct BedFiles {
  std::string prefix;
  std::string key;
  std::string mode;  ///< slab | box
  long grains = 0;
  double Lx_m = 0, Ly_m = 0, H_m = 0;
  double z_surface_m = 0;                     ///< levelled surface (mean top of the top layer)
  double z_box_top_m = 0;                     ///< top of the simulation box
  double r_max_m = 0;                         ///< largest grain radius
  double dt_s = 0;                            ///< time step
  double settle_time_s = 0;                   ///< simulated time to pour and settle
  bool settled = false;                       ///< the settling criterion was met
  std::map<std::string, std::string> values;  ///< every variable of PREFIX.params
};

/// Reads PREFIX.params. Throws std::runtime_error naming the file when it is missing or incomplete.
BedFiles read_bed_files(const std::string& prefix);

/// The path prefix of the bed with key `key` in `cache_dir`: CACHE_DIR/bed-KEY (its files are
/// PREFIX.restart, .params, .screen, .log, .lock).
std::string bed_prefix(const std::string& cache_dir, const std::string& key);

/// Whether `cache_dir` holds the bed with key `key` (its .restart and .params), as ensure_bed
/// reuses it.
bool bed_cached(const std::string& cache_dir, const std::string& key);

/// Whether a process is building that bed now: ensure_bed holds PREFIX.lock exclusively from its
/// cache check to the end of the build (a lock that cannot be shared at once).
bool bed_building(const std::string& cache_dir, const std::string& key);

/// A checkpoint of a bed build that a kill interrupted (liggghts-inputs/bed/chunks.in): the file
/// PREFIX.building.ckpt-PHASE-CHUNK-SETTLED.restart, whose name is its state. Phases: 1 the pour's
/// free fall, 2 its settling, 3 the settling after the levelling; `chunk` of them are done (of
/// check_every steps each); `settled_pour` whether the pour had settled (phase 3).
struct BedCheckpoint {
  std::string path;
  int phase = 0;
  long chunk = 0;
  int settled_pour = 0;
};

/// The latest checkpoint (highest phase, then chunk) of the build whose files start with
/// `building_prefix` (PREFIX.building), or nullopt. Names that do not parse are ignored.
std::optional<BedCheckpoint> latest_bed_checkpoint(const std::string& building_prefix);

/// The bed for `bed_overrides` in `cache_dir`: reused when cache_dir/bed-KEY.{restart,params}
/// exist, otherwise built on `comm` (collective: every rank of comm calls it) with screen and log
/// in cache_dir/bed-KEY.{screen,log}. `built` (optional) tells whether it was built now.
/// `checkpoint_steps` > 0: the build writes a checkpoint about every that many steps (rounded up
/// to whole settling checks, the bed's check_every), and a build that a kill interrupted resumes
/// from its latest checkpoint (said on stderr by rank 0); the same number as the impacts'
/// run.checkpoint_steps (checkpoint_steps_of). 0: no checkpoints.
BedFiles ensure_bed(const Decks& decks, const std::map<std::string, std::string>& bed_overrides,
                    const std::string& cache_dir, MPI_Comm comm, bool* built = nullptr,
                    double* wall_s = nullptr, long checkpoint_steps = 0);

/// The packing of a built bed, measured on its restart file (issue 32, item 2: the bulk
/// constraint of a sand-like bed).
///   solid fraction  phi = sum_i (4/3) pi r_i^3 / (Lx Ly z_surface)
/// over every grain of the bed (in.bed: floor at z = 0, levelled surface z_surface, the mean top
/// of the top layer; the grains that stand above it are few and count whole), and the bulk density
/// rho_b = phi rho_grain. The same definition as a soil's dry density over its container's volume
/// (Lambe and Whitman 1969, Soil Mechanics, ch. 3).
struct BedPacking {
  long grains = 0;                ///< grains in the restart file
  double grain_volume_m3 = 0;     ///< sum of the grains' volumes [m^3]
  double bed_volume_m3 = 0;       ///< Lx Ly z_surface [m^3]
  double solid_fraction = 0;      ///< grain_volume / bed_volume [-]
  double bulk_density_kg_m3 = 0;  ///< solid_fraction x rho_grain [kg/m^3]
};

/// The solid fraction of a bed known only by its grain count N (every impact's index row keeps it,
/// /dem/index/values "grains"), from reference beds of the same box, depth and grain sizes whose
/// packing was measured (measure_packing):
///   phi = N vbar / (Lx Ly z_surface)   (measure_packing's definition, vbar the mean grain volume)
/// with the factor f = vbar / (Lx Ly z_surface) averaged over the references. It holds where
/// neither the mean grain volume (the same size distribution) nor the levelled surface (the same
/// H_m) depends on the grain law; `loo_max_abs` checks that on the references themselves. Used by
/// calibrate-grains for beds that neither the campaign file records nor any cache holds.
struct GrainCountPacking {
  std::size_t references = 0;
  double per_grain = NAN;    ///< mean f over the references [1/grain]
  double loo_max_abs = NAN;  ///< max |phi_i - N_i mean_{j != i} f_j| over references [-] (>= 2)
  double solid_fraction(long grains) const { return static_cast<double>(grains) * per_grain; }
};

/// The estimator of GrainCountPacking from `references`. Throws std::invalid_argument when there
/// is none or one has no grain or no volume.
GrainCountPacking grain_count_packing(const std::vector<BedPacking>& references);

/// Measures `bed`'s packing (collective on `comm`): a LIGGGHTS instance reads PREFIX.restart and
/// sums the grains' volumes over the ranks; its log and screen go to PREFIX.packing.{log,screen}.
/// Throws std::runtime_error naming the file when the restart is missing or holds no grain.
BedPacking measure_packing(const BedFiles& bed, MPI_Comm comm);

}  // namespace ricochet::dem
