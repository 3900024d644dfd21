#include "engine/shape.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/error.hpp"

namespace ricochet {

bool Shape::is_disc() const {
  return vertices.size() == 1 && vertices[0][0] == 0.0 && vertices[0][1] == 0.0;
}

double Shape::depth_below_centroid(double alpha_rad) const {
  return -lowest_point(alpha_rad)[1];
}

std::array<double, 2> Shape::lowest_point(double alpha_rad) const {
  const double c = std::cos(alpha_rad), s = std::sin(alpha_rad);
  std::size_t low = 0;
  double y_low = 0;
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const double y = s * vertices[k][0] + c * vertices[k][1];
    if (k == 0 || y < y_low) {
      y_low = y;
      low = k;
    }
  }
  const double x = vertices.empty() ? 0.0 : c * vertices[low][0] - s * vertices[low][1];
  return {x, y_low - rounding_radius_m};
}

double Shape::bounding_radius() const {
  double r = 0;
  for (const auto& v : vertices) r = std::max(r, std::hypot(v[0], v[1]));
  return r + rounding_radius_m;
}

Shape Shape::cylinder() {
  return Shape{"cylinder", {{0.0, 0.0}}, 0.08, 13.9, 0.0445, 0.29};
}

Shape Shape::triangle() {
  // Keep in sync with data/shapes/triangle.toml (a test compares them).
  return Shape{"triangle", {{0.000000, 0.100300}, {-0.086862, -0.050150}, {0.086862, -0.050150}},
               0.010,      10.89,
               0.0383,     0.246};
}

namespace {
std::size_t line_of(const toml::node& n) {
  return static_cast<std::size_t>(n.source().begin.line);
}

// A finite number; `positive`: also > 0. Errors name the key's line.
double number_at(const toml::node& n, const char* key, const std::string& file, bool positive) {
  const auto v = n.value<double>();
  if (!v || !std::isfinite(*v)) throw InputError(file, line_of(n), key, "expected a finite number");
  if (positive && !(*v > 0)) throw InputError(file, line_of(n), key, "must be > 0");
  return *v;
}

double require_positive(const toml::table& t, const char* key, const std::string& file) {
  const toml::node* n = t.get(key);
  if (!n) throw InputError(file, 0, key, "missing");
  return number_at(*n, key, file, true);
}
}  // namespace

Shape Shape::from_toml_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the shape file");
  std::ostringstream text;
  text << in.rdbuf();
  return from_toml_string(text.str(), path);
}

Shape Shape::from_toml_string(const std::string& text, const std::string& path) {
  toml::table t;
  try {
    t = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw InputError(path, static_cast<std::size_t>(e.source().begin.line), "",
                     std::string(e.description()));
  }
  Shape s;
  s.name = "custom";
  if (const toml::node* n = t.get("name")) {
    const auto name = n->value<std::string>();
    if (!name) throw InputError(path, line_of(*n), "name", "expected a string");
    s.name = *name;
  }
  const toml::node* verts_node = t.get("vertices");
  const toml::array* verts = verts_node ? verts_node->as_array() : nullptr;
  if (!verts || verts->empty())
    throw InputError(path, verts_node ? line_of(*verts_node) : 0, "vertices",
                     "missing list of [x, y] vertices in metres");
  for (const auto& v : *verts) {
    const toml::array* xy = v.as_array();
    const auto line = line_of(v);
    if (!xy || xy->size() != 2 || !xy->get(0)->value<double>() || !xy->get(1)->value<double>())
      throw InputError(path, line, "vertices", "each vertex must be [x, y] in metres");
    const double x = *xy->get(0)->value<double>(), y = *xy->get(1)->value<double>();
    if (!std::isfinite(x) || !std::isfinite(y))
      throw InputError(path, line, "vertices", "vertex coordinates must be finite");
    s.vertices.push_back({x, y});
  }
  s.rounding_radius_m = require_positive(t, "rounding_radius_m", path);
  s.mass_kg = require_positive(t, "mass_kg", path);
  s.inertia_kgm2 = require_positive(t, "inertia_kgm2", path);
  if (const toml::node* n = t.get("length_m")) {
    s.length_m = number_at(*n, "length_m", path, false);
    if (s.length_m < 0) throw InputError(path, line_of(*n), "length_m", "must be >= 0");
  }
  // The centroid must be the centre of mass: the engine's lever arms assume it.
  double cx = 0, cy = 0;
  for (const auto& v : s.vertices) {
    cx += v[0];
    cy += v[1];
  }
  cx /= static_cast<double>(s.vertices.size());
  cy /= static_cast<double>(s.vertices.size());
  if (!(std::hypot(cx, cy) <= 1e-3 * s.bounding_radius()))
    throw InputError(path, line_of(*verts_node), "vertices",
                     "the vertices' mean must be at the origin (the centre of mass)");
  return s;
}

Shape Shape::resolve(const std::string& name_or_path) {
  if (name_or_path == "cylinder") return cylinder();
  if (name_or_path == "triangle") return triangle();
  if (name_or_path.find('.') == std::string::npos && name_or_path.find('/') == std::string::npos)
    throw InputError(
        "<command line>", 0, "--shape",
        "unknown shape '" + name_or_path + "'; use cylinder, triangle, or a shape file (.toml)");
  return from_toml_file(name_or_path);
}

void Ground::surface(double x, double& height, double& nx, double& ny) const {
  if (x_m.size() < 2) {
    height = x_m.empty() ? 0.0 : y_m[0];
    nx = 0;
    ny = 1;
    return;
  }
  std::size_t k = 0;
  while (k + 2 < x_m.size() && x >= x_m[k + 1]) ++k;
  const double dx = x_m[k + 1] - x_m[k], dy = y_m[k + 1] - y_m[k];
  height = y_m[k] + dy * (x - x_m[k]) / dx;
  const double len = std::hypot(dx, dy);
  nx = -dy / len;
  ny = dx / len;
}

}  // namespace ricochet
