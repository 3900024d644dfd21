#include "block_template.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>

namespace ricochet::dem {

namespace {

using Point = std::array<double, 2>;

// Points along the boundary of the convex polygon `poly` dilated by `d`, at most `spacing` apart
// on its straight parts and `arc_spacing` apart on its arcs, including every polygon vertex's
// offset points (so the corners of a sharp core are covered).
std::vector<Point> offset_ring(std::vector<Point> poly, double d, double spacing,
                               double arc_spacing) {
  std::vector<Point> ring;
  if (poly.size() == 1) {
    if (d <= 0) return poly;
    const auto n = static_cast<std::size_t>(std::ceil(2 * std::numbers::pi * d / arc_spacing));
    for (std::size_t k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n);
      ring.push_back({poly[0][0] + d * std::cos(a), poly[0][1] + d * std::sin(a)});
    }
    return ring;
  }
  // Counter-clockwise order so that the outward normal of edge (a, b) is (by - ay, ax - bx).
  double area2 = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Point& a = poly[i];
    const Point& b = poly[(i + 1) % poly.size()];
    area2 += a[0] * b[1] - b[0] * a[1];
  }
  if (area2 < 0) std::reverse(poly.begin(), poly.end());
  const std::size_t n = poly.size();
  auto normal = [&](std::size_t i) {
    const Point& a = poly[i];
    const Point& b = poly[(i + 1) % n];
    const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
    return Point{(b[1] - a[1]) / len, (a[0] - b[0]) / len};
  };
  for (std::size_t i = 0; i < n; ++i) {
    // Arc around vertex i from the previous edge's normal to this edge's normal.
    const Point n0 = normal((i + n - 1) % n), n1 = normal(i);
    const double a0 = std::atan2(n0[1], n0[0]);
    double sweep = std::atan2(n1[1], n1[0]) - a0;
    while (sweep < 0) sweep += 2 * std::numbers::pi;
    const auto n_arc = d > 0 ? static_cast<std::size_t>(std::ceil(sweep * d / arc_spacing)) : 0;
    if (d <= 0) ring.push_back(poly[i]);
    for (std::size_t k = 0; k < n_arc; ++k) {
      const double a = a0 + sweep * static_cast<double>(k) / static_cast<double>(n_arc);
      ring.push_back({poly[i][0] + d * std::cos(a), poly[i][1] + d * std::sin(a)});
    }
    // Edge i shifted outward by d, from its start (inclusive) to its end (exclusive).
    const Point& a = poly[i];
    const Point& b = poly[(i + 1) % n];
    const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
    const auto n_edge =
        std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(len / spacing)));
    for (std::size_t k = 0; k < n_edge; ++k) {
      if (k == 0 && d <= 0) continue;  // the vertex itself was pushed above
      const double t = static_cast<double>(k) / static_cast<double>(n_edge);
      ring.push_back({a[0] + t * (b[0] - a[0]) + d * n1[0], a[1] + t * (b[1] - a[1]) + d * n1[1]});
    }
  }
  return ring;
}

}  // namespace

SphereTemplate make_sphere_template(const Shape& shape, double length_m,
                                    const TemplateOptions& options) {
  if (!(length_m > 0)) throw std::invalid_argument("block template: length must be > 0 m");
  if (!(shape.length_m > 0))
    throw std::invalid_argument("block template: shape '" + shape.name +
                                "' has no length_m (needed to scale mass and inertia)");
  if (!(options.bump_tolerance_m > 0) || !(options.max_sphere_radius_m > 0))
    throw std::invalid_argument("block template: tolerance and sphere radius must be > 0 m");
  SphereTemplate t;
  t.shape_name = shape.name;
  t.length_m = length_m;
  t.sphere_radius_m = std::min(shape.rounding_radius_m, options.max_sphere_radius_m);
  // Sagitta of a circle of radius r_s over a chord c is about c^2 / (8 r_s): c = sqrt(8 r_s tol).
  // Never more than r_s apart, so that no grain can slip between two spheres into the shell.
  t.spacing_m =
      std::min(std::sqrt(8 * t.sphere_radius_m * options.bump_tolerance_m), t.sphere_radius_m);
  const double d = shape.rounding_radius_m - t.sphere_radius_m;
  std::vector<Point> poly(shape.vertices.begin(), shape.vertices.end());
  // On an arc of centre radius d the surface (radius d + r_s) is farther from the centres than
  // on a straight part: the bump grows by (d + r_s) / d, so the arc spacing shrinks by its root.
  const double arc_spacing = t.spacing_m * std::sqrt(d / (d + t.sphere_radius_m));
  const std::vector<Point> ring = offset_ring(poly, d, t.spacing_m, arc_spacing);

  const double r_s = t.sphere_radius_m;
  // Slab: the end rings sit a tenth of a sphere radius inside the side walls (a sphere centred on
  // the box boundary is lost at insertion), which narrows the section at the wall by under
  // 0.5 % of r_s. Box: the ends are rounded inside the length.
  const double y_end =
      options.full_section_at_ends ? 0.5 * length_m - 0.1 * r_s : 0.5 * length_m - r_s;
  if (y_end < 0)
    throw std::invalid_argument(fmt::format(
        "block template: length {} m is shorter than a sphere diameter {} m", length_m, 2 * r_s));
  const auto n_axial =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(2 * y_end / t.spacing_m)));
  for (std::size_t k = 0; k <= n_axial; ++k) {
    const double y = -y_end + 2 * y_end * static_cast<double>(k) / static_cast<double>(n_axial);
    for (const Point& p : ring) t.spheres.push_back({p[0], y, p[1], r_s});
  }
  t.bounding_radius_m = shape.bounding_radius();
  t.vertices = shape.vertices;
  t.rounding_radius_m = shape.rounding_radius_m;

  // Mass and inertia per unit length are the lab block's: a slab of width w carries the fraction
  // w / L of the block (planar motion, so velocities do not depend on the fraction).
  const double fraction = length_m / shape.length_m;
  t.mass_kg = shape.mass_kg * fraction;
  t.inertia_axis_kgm2 = shape.inertia_kgm2 * fraction;
  // Transverse moments only enter through the principal-axis computation (tflag freezes those
  // rotations): take those of a prism whose section has polar moment I/m split equally between its
  // two axes (perpendicular-axis theorem), plus the length term m w^2 / 12.
  t.inertia_transverse_kgm2 =
      t.mass_kg * (0.5 * shape.inertia_kgm2 / shape.mass_kg + length_m * length_m / 12.0);
  return t;
}

void write_sphere_file(const SphereTemplate& t, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write sphere template " + path);
  out << fmt::format(
      "# Multisphere template of the '{}' block, generated by `ricochet dem template` from the\n"
      "# shape file (src-ext/block_template.hpp). LIGGGHTS frame: x flight, y axis, z up; metres.\n"
      "# length {} m, {} spheres of radius {} m, spacing {} m; mass {} kg, I_yy {} kg m^2\n",
      t.shape_name, t.length_m, t.spheres.size(), t.sphere_radius_m, t.spacing_m, t.mass_kg,
      t.inertia_axis_kgm2);
  for (const auto& s : t.spheres)
    out << fmt::format("{:.6f} {:.6f} {:.6f} {:.6f}\n", s[0], s[1], s[2], s[3]);
  if (!out) throw std::runtime_error("error writing sphere template " + path);
}

void write_template_include(const SphereTemplate& t, const std::string& sphere_file,
                            const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write template include " + path);
  out << fmt::format(
      "# Block template variables for the impact deck, generated by `ricochet dem template`.\n"
      "# Shape '{}', modelled length {} m (mass and inertia scaled from the lab block).\n"
      "variable block_template_file index {}\n"
      "variable block_nspheres index {}\n"
      "variable block_mass_kg index {:.9g}\n"
      "variable block_Iyy_kgm2 index {:.9g}\n"
      "variable block_Ixx_kgm2 index {:.9g}\n"
      "variable block_length_m index {:.9g}\n"
      "variable block_bounding_radius_m index {:.9g}\n",
      t.shape_name, t.length_m, sphere_file, t.spheres.size(), t.mass_kg, t.inertia_axis_kgm2,
      t.inertia_transverse_kgm2, t.length_m, t.bounding_radius_m);
  // Height of each vertex above the centroid after a counter-clockwise rotation by alpha, then
  // their minimum as a chain of two-term minima (LIGGGHTS formulas have no min()).
  for (std::size_t k = 0; k < t.vertices.size(); ++k)
    out << fmt::format(
        "variable block_vy{} equal sin(v_alpha_in_rad)*({:.9g})+cos(v_alpha_in_rad)*({:.9g})\n", k,
        t.vertices[k][0], t.vertices[k][1]);
  out << "variable block_vmin0 equal v_block_vy0\n";
  for (std::size_t k = 1; k < t.vertices.size(); ++k)
    out << fmt::format(
        "variable block_vmin{0} equal (v_block_vmin{1}<v_block_vy{0})*v_block_vmin{1}+"
        "(v_block_vmin{1}>=v_block_vy{0})*v_block_vy{0}\n",
        k, k - 1);
  out << fmt::format("variable block_depth_m equal {:.9g}-v_block_vmin{}\n", t.rounding_radius_m,
                     t.vertices.size() - 1);
  if (!out) throw std::runtime_error("error writing template include " + path);
}

std::array<double, 4> quaternion_from_alpha(double alpha_rad) {
  return {std::cos(-0.5 * alpha_rad), 0.0, std::sin(-0.5 * alpha_rad), 0.0};
}

double alpha_from_quaternion(const std::array<double, 4>& q) {
  return -2.0 * std::atan2(q[2], q[0]);
}

}  // namespace ricochet::dem
