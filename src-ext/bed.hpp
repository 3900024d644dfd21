// Settled beds: built once with liggghts-inputs/bed/in.bed and cached by the hash of their
// parameters (bed_key), so every impact on the same bed, in this run or a later one, reuses it.
#pragma once

#include <mpi.h>

#include <map>
#include <string>

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

/// The bed for `bed_overrides` in `cache_dir`: reused when cache_dir/bed-KEY.{restart,params}
/// exist, otherwise built on `comm` (collective: every rank of comm calls it) with screen and log
/// in cache_dir/bed-KEY.{screen,log}. `built` (optional) tells whether it was built now.
BedFiles ensure_bed(const Decks& decks, const std::map<std::string, std::string>& bed_overrides,
                    const std::string& cache_dir, MPI_Comm comm, bool* built = nullptr,
                    double* wall_s = nullptr);

}  // namespace ricochet::dem
