// The block as a LIGGGHTS multisphere body, generated from the same sphero-polygon geometry as the
// reduced engine (engine/shape.hpp, data/shapes/*.toml).
//
// A sphero-polygon (core polygon P dilated by the rounding radius r) is reproduced exactly, up to
// small bumps, by spheres of radius r_s <= r whose centres lie on the boundary of P dilated by
// (r - r_s): every such sphere touches the true surface from inside, and neighbouring spheres
// closer than sqrt(8 r_s tol) apart leave bumps no deeper than tol (sagitta of a circle of radius
// r_s over a chord of that length). The same ring is repeated along the block axis with the same
// spacing. Mass and inertia are PRESCRIBED (the lab's values, scaled by the modelled length over
// the lab length in a slab), so the sphere union only carries the contact geometry.
//
// Frames. Body frame of the shape file: x in the flight direction, y up (the paper's 2-D frame).
// LIGGGHTS frame: x flight direction, z up, y along the block axis. So (x, y)_paper -> (x, z) and
// a counter-clockwise paper angle alpha is a rotation by -alpha about +y:
//   omega_y(LIGGGHTS) = -omega(paper),  quaternion = (cos(-alpha/2), 0, sin(-alpha/2), 0).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "engine/shape.hpp"

namespace ricochet::dem {

struct TemplateOptions {
  /// Largest template sphere radius [m]; the rounding radius when smaller. Small spheres keep
  /// LIGGGHTS's neighbour bins small (bins scale with the largest sphere).
  double max_sphere_radius_m = 0.015;
  /// Largest bump depth between neighbouring spheres [m].
  double bump_tolerance_m = 0.0005;
  /// true (slab): sphere centres span the whole modelled length so the full cross-section
  /// reaches the slab's side walls; false (3-D box): the ends are rounded inside the length.
  bool full_section_at_ends = true;
};

/// A generated multisphere template in the LIGGGHTS frame.
struct SphereTemplate {
  std::string shape_name;
  std::vector<std::array<double, 4>> spheres;  ///< x, y, z, radius [m]; centroid at the origin
  double length_m = 0;                         ///< modelled length along the axis y [m]
  double mass_kg = 0;                          ///< lab mass scaled by length_m / shape.length_m
  double inertia_axis_kgm2 = 0;        ///< lab inertia about the axis, scaled likewise (I_yy)
  double inertia_transverse_kgm2 = 0;  ///< I_xx = I_zz (irrelevant in planar motion; see .cpp)
  double bounding_radius_m = 0;        ///< largest distance of the section surface from the axis
  std::vector<std::array<double, 2>> vertices;  ///< the shape's core polygon (paper frame) [m]
  double rounding_radius_m = 0;                 ///< the shape's rounding radius [m]
  double sphere_radius_m = 0;
  double spacing_m = 0;  ///< centre spacing along the ring and along the axis
};

/// Generates the template of `shape` for a modelled length `length_m` (the slab width in a
/// quasi-2-D bed, the block length in a 3-D box). Throws std::invalid_argument for a shape
/// without length, a non-positive length or tolerance.
SphereTemplate make_sphere_template(const Shape& shape, double length_m,
                                    const TemplateOptions& options = {});

/// Writes the template as a LIGGGHTS sphere file ("x y z r" per line, '#' comments carrying the
/// provenance) for `fix particletemplate/multisphere ... spheres file F scale 1.0`.
void write_sphere_file(const SphereTemplate& t, const std::string& path);

/// Writes a LIGGGHTS include file defining the template's variables (block_template_file,
/// block_nspheres, block_mass_kg, block_Iyy_kgm2, block_Ixx_kgm2, block_length_m,
/// block_bounding_radius_m) as index variables, for the impact deck, and the equal-style
/// block_depth_m: the depth of the block's lowest point below its centroid at orientation
/// v_alpha_in_rad, r - min_k (sin(alpha) x_k + cos(alpha) y_k) over the vertices (x_k, y_k)
/// (the same formula as Shape::depth_below_centroid).
void write_template_include(const SphereTemplate& t, const std::string& sphere_file,
                            const std::string& path);

/// LIGGGHTS quaternion (w, x, y, z) of a block whose paper-frame orientation is `alpha_rad`.
std::array<double, 4> quaternion_from_alpha(double alpha_rad);
/// Paper-frame orientation angle [rad] of a LIGGGHTS quaternion (rotation about y only).
double alpha_from_quaternion(const std::array<double, 4>& q);

}  // namespace ricochet::dem
