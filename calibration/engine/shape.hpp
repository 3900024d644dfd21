// Rigid 2-D blocks as sphero-polygons: a convex polygon dilated by a rounding radius.
// A disc is the polygon of one vertex at its centroid dilated by its radius.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace ricochet {

struct Shape {
  std::string name;
  /// Polygon vertices in the body frame [m], centroid (centre of mass) at the origin.
  std::vector<std::array<double, 2>> vertices;
  double rounding_radius_m = 0;  ///< dilation radius r [m]
  double mass_kg = 0;
  double inertia_kgm2 = 0;  ///< moment of inertia about the axis through the centroid
  double length_m = 0;      ///< extent along the block axis (per-length laws, LIGGGHTS template)

  /// One vertex at the origin: contact geometry needs no rotation.
  bool is_disc() const;
  /// Lowest point of the block below its centroid when rotated by `alpha_rad`, as a positive
  /// distance [m] (r - min_v (R(alpha) v)_y).
  double depth_below_centroid(double alpha_rad) const;
  /// That lowest point relative to the centroid [m] (x, y; y = -depth_below_centroid): the
  /// lowest vertex turned by `alpha_rad` (counter-clockwise), less the rounding radius below it.
  std::array<double, 2> lowest_point(double alpha_rad) const;
  /// Largest distance of the surface from the centroid [m].
  double bounding_radius() const;

  /// The lab cylinder: R = 0.08 m, m = 13.9 kg, I = 0.0445 kg m^2 (paper Fig. 4), length 0.29 m.
  static Shape cylinder();
  /// The lab triangle with truncated vertices: m = 10.89 kg, I = 0.0383 kg m^2 (paper Fig. 4),
  /// geometry of data/shapes/triangle.toml (equilateral side 0.1737 m, rounding 0.010 m).
  static Shape triangle();
  /// Reads a shape file (TOML: name, vertices, rounding_radius_m, mass_kg, inertia_kgm2,
  /// length_m). Throws InputError naming file, line and key.
  static Shape from_toml_file(const std::string& path);
  /// Same from TOML text; `name` is the file named in errors (used by the fuzz target).
  static Shape from_toml_string(const std::string& text, const std::string& name);
  /// "cylinder", "triangle", or a path to a shape file.
  static Shape resolve(const std::string& name_or_path);
};

/// Ground surface: a polyline y(x) [m]; empty = flat ground y = 0. Outside the polyline's
/// x-range the end segments extend.
struct Ground {
  std::vector<double> x_m, y_m;
  bool flat() const { return x_m.empty(); }
  /// Height and unit normal (pointing out of the ground) at abscissa x.
  void surface(double x, double& height, double& nx, double& ny) const;
};

}  // namespace ricochet
