// A picture of one resolved impact, kept in its campaign file: a thin section of the bed through
// the block's mid-plane (the side view of the lab's camera), at a few frames through the contact.
// Written by `ricochet dem campaign` for the campaign's first impact; drawn by the report and by
// `upscale --figures` (report/impact_picture.hpp). Stored under /dem/snapshot of the campaign
// file (docs/commands/dem.md, "Campaign file"): attributes impact_id, section_y_m,
// section_half_width_m, and one group frame_K per frame with attributes step, t_s,
// max_penetration (1 or 0) and two datasets, grains (n x 4: x [m], z [m], speed [m/s], radius
// [m]) and block (m x 3: x [m], z [m], radius [m] of the block's spheres).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace ricochet {

/// One frame: the grains of the section and all of the block's spheres, in the paper's plane (x
/// along the bed, z up; the section is |y - section_y_m| <= section_half_width_m).
struct SnapshotFrame {
  long step = 0;
  double t_s = 0;                ///< time since the first frame in contact [s]
  bool max_penetration = false;  ///< the frame where the block is deepest
  std::vector<double> grain_x_m, grain_z_m, grain_speed_mps, grain_radius_m;
  std::vector<double> block_x_m, block_z_m, block_radius_m;
};

struct ImpactSnapshot {
  std::string impact_id;
  double section_y_m = 0, section_half_width_m = 0;
  std::vector<SnapshotFrame> frames;  ///< in time order
};

/// Writes (replacing) /dem/snapshot of the HDF5 file `path` (created if missing). Throws
/// std::runtime_error naming the file on failure, std::invalid_argument for a frame whose
/// columns differ in length.
void write_snapshot(const std::string& path, const ImpactSnapshot& snapshot);

/// The snapshot of a campaign file; nullopt when `path` is not an HDF5 file or has none. Throws
/// std::runtime_error naming the file and the object for a malformed snapshot.
std::optional<ImpactSnapshot> read_snapshot(const std::string& path);

}  // namespace ricochet
