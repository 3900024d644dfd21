// Frames of a resolved impact written by the impact deck, read back: LIGGGHTS's VTK frames
// (`dump custom/vtk`, --vtk, for ParaView; legacy VTK format, "The VTK User's Guide" 11th ed.,
// "VTK File Formats") and its plain text dumps (`dump custom`, the picture's frames), and the
// impact picture (impact/impact_snapshot.hpp) cut from the text dumps.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "impact/impact_snapshot.hpp"

namespace ricochet::dem {

/// The particles of one frame: positions [m], velocities [m/s], radii [m], ids.
struct Particles {
  std::vector<std::array<double, 3>> x, v;
  std::vector<double> radius;
  std::vector<long> id;
  std::size_t size() const { return x.size(); }
};

/// Reads one ASCII legacy VTK POLYDATA file as LIGGGHTS writes it (POINTS, VERTICES in the 5.1
/// OFFSETS/CONNECTIVITY form or the older one, POINT_DATA with a FIELD of arrays id, type, v,
/// radius). Checks the format: every count matches the data that follows, v has 3 components,
/// every array has one tuple per point. Throws InputError naming the file and the section.
Particles read_vtk_particles(const std::string& path);

/// Reads one LIGGGHTS text dump (`dump custom ... id type x y z vx vy vz radius`: "ITEM:"
/// headers, NUMBER OF ATOMS, then ATOMS with those columns in any order). Throws InputError
/// naming the file, the line and the column.
Particles read_dump_particles(const std::string& path);

/// Steps of the frames in `dir` with extension `ext` (".vtk" or ".txt"): grains_STEP.EXT with a
/// block_STEP.EXT beside it, sorted.
std::vector<long> frame_steps(const std::string& dir, const std::string& ext = ".vtk");

/// The impact picture from the text dumps of one impact in `dir` (grains_STEP.txt,
/// block_STEP.txt): the block's deepest point over
/// the frames, the frames in contact (block below the bed's initial surface, the top of the
/// first frame's grains), up to `frames` of them evenly spread, the deepest always included; in
/// each, the grains of a section one largest grain radius either side of the block's mid-plane,
/// cropped to one block radius around the block (its centres' path widened by two radii). `dt_s`
/// converts steps to time, counted from the first frame in contact. Throws InputError when `dir`
/// has no frame or no frame in contact.
ImpactSnapshot snapshot_from_frames(const std::string& dir, const std::string& impact_id,
                                    double dt_s, int frames = 5);

}  // namespace ricochet::dem
