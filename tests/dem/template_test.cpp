// Multisphere templates: the sphere union reproduces the sphero-polygon of the shape file (no
// sphere outside it, every surface point covered within the bump tolerance), mass and inertia scale
// with the modelled length, frames map as documented, and the deck's committed templates are the
// generator's output.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "block_template.hpp"
#include "engine/shape.hpp"

namespace {

using ricochet::Shape;
using namespace ricochet::dem;
namespace fs = std::filesystem;

// Distance from p to the core polygon (0 inside): the sphero-polygon is {p : dist <= r}.
double dist_to_core(const Shape& s, double x, double y) {
  const auto& v = s.vertices;
  if (v.size() == 1) return std::hypot(x - v[0][0], y - v[0][1]);
  bool inside = true;
  double best = 1e9;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& a = v[i];
    const auto& b = v[(i + 1) % v.size()];
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    const double t =
        std::clamp(((x - a[0]) * ex + (y - a[1]) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    best = std::min(best, std::hypot(x - a[0] - t * ex, y - a[1] - t * ey));
    // Counter-clockwise polygon: inside is to the left of every edge.
    if (ex * (y - a[1]) - ey * (x - a[0]) < 0) inside = false;
  }
  return inside ? 0.0 : best;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class TemplateShapes : public ::testing::TestWithParam<const char*> {};

TEST_P(TemplateShapes, SpheresStayInsideTheShapeAndCoverItsSurface) {
  const Shape shape = Shape::resolve(GetParam());
  TemplateOptions o;
  const auto t = make_sphere_template(shape, 0.1, o);
  ASSERT_GT(t.spheres.size(), 10u);
  const double r = shape.rounding_radius_m;
  for (const auto& s : t.spheres) {
    // A sphere inside the shape: centre at most r - r_s from the core.
    EXPECT_LE(dist_to_core(shape, s[0], s[2]) + s[3], r + 1e-9);
    EXPECT_LE(std::abs(s[1]), 0.05 + 1e-12);
  }
  // Surface points of the true section (at mid-length): the deepest gap to the sphere union.
  double worst_gap = 0;
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * std::numbers::pi * k / 2000.0;
    // March outwards along direction a until leaving the shape: a surface point.
    double lo = 0, hi = 1;
    for (int it = 0; it < 60; ++it) {
      const double m = 0.5 * (lo + hi);
      (dist_to_core(shape, m * std::cos(a), m * std::sin(a)) <= r ? lo : hi) = m;
    }
    const double px = lo * std::cos(a), pz = lo * std::sin(a);
    double covered = -1e9;  // largest (r_s - distance) over spheres of the mid ring
    for (const auto& s : t.spheres)
      if (std::abs(s[1]) < 0.5 * t.spacing_m)
        covered = std::max(covered, s[3] - std::hypot(px - s[0], pz - s[2]));
    worst_gap = std::max(worst_gap, -covered);
  }
  EXPECT_LE(worst_gap, o.bump_tolerance_m * 1.05) << GetParam();
}

TEST_P(TemplateShapes, MassAndInertiaScaleWithTheModelledLength) {
  const Shape shape = Shape::resolve(GetParam());
  const auto full = make_sphere_template(shape, shape.length_m);
  const auto slab = make_sphere_template(shape, 0.1);
  EXPECT_NEAR(full.mass_kg, shape.mass_kg, 1e-12);
  EXPECT_NEAR(full.inertia_axis_kgm2, shape.inertia_kgm2, 1e-12);
  EXPECT_NEAR(slab.mass_kg / slab.inertia_axis_kgm2, shape.mass_kg / shape.inertia_kgm2, 1e-9);
  EXPECT_NEAR(slab.mass_kg, shape.mass_kg * 0.1 / shape.length_m, 1e-12);
  EXPECT_GT(full.spheres.size(), slab.spheres.size());
}

INSTANTIATE_TEST_SUITE_P(LabBlocks, TemplateShapes, ::testing::Values("cylinder", "triangle"));

TEST(Template, SlabEndsReachTheWallsBoxEndsAreRounded) {
  const Shape c = Shape::cylinder();
  TemplateOptions slab, box;
  box.full_section_at_ends = false;
  const auto ts = make_sphere_template(c, 0.1, slab);
  const auto tb = make_sphere_template(c, 0.1, box);
  double ys = 0, yb = 0;
  for (const auto& s : ts.spheres) ys = std::max(ys, s[1]);
  for (const auto& s : tb.spheres) yb = std::max(yb, s[1] + s[3]);
  EXPECT_NEAR(ys, 0.05 - 0.1 * ts.sphere_radius_m, 1e-9);  // full section up to the wall
  EXPECT_NEAR(yb, 0.05, 1e-9);                             // nothing beyond the block's end
}

TEST(Template, RejectsMeaninglessInput) {
  EXPECT_THROW(make_sphere_template(Shape::cylinder(), 0.0), std::invalid_argument);
  Shape no_length = Shape::cylinder();
  no_length.length_m = 0;
  EXPECT_THROW(make_sphere_template(no_length, 0.1), std::invalid_argument);
  TemplateOptions o;
  o.bump_tolerance_m = 0;
  EXPECT_THROW(make_sphere_template(Shape::cylinder(), 0.1, o), std::invalid_argument);
}

TEST(Template, QuaternionMapsThePaperAngle) {
  for (double alpha : {0.0, 0.3, -1.2, 2.5}) {
    const auto q = quaternion_from_alpha(alpha);
    EXPECT_NEAR(q[0] * q[0] + q[2] * q[2], 1.0, 1e-12);
    EXPECT_NEAR(alpha_from_quaternion(q), alpha, 1e-12);
    // Rotating the body point (x, z) = (1, 0) by the quaternion about y must give the paper's
    // counter-clockwise rotation by alpha in (x, y): z' = sin(alpha).
    const double th = 2 * std::atan2(q[2], q[0]);  // rotation angle about +y
    EXPECT_NEAR(-std::sin(th), std::sin(alpha), 1e-12);
  }
}

TEST(Template, DepthFormulaInTheIncludeMatchesTheEngine) {
  const Shape tri = Shape::triangle();
  const auto t = make_sphere_template(tri, 0.1);
  const fs::path dir = fs::temp_directory_path() / ("dem-tpl-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_template_include(t, "x.ms", (dir / "t.in").string());
  const std::string text = read(dir / "t.in");
  fs::remove_all(dir);
  EXPECT_NE(text.find("variable block_depth_m equal 0.01-v_block_vmin2"), std::string::npos);
  // Evaluate the generated formula by hand at alpha = 0.4 and compare with the engine.
  const double a = 0.4;
  double lowest = 1e9;
  for (const auto& v : tri.vertices)
    lowest = std::min(lowest, std::sin(a) * v[0] + std::cos(a) * v[1]);
  EXPECT_NEAR(tri.rounding_radius_m - lowest, tri.depth_below_centroid(a), 1e-12);
}

// The deck's committed templates must be exactly what `ricochet dem template` writes today, so
// that the plain deck and the driver use the same block.
TEST(Template, CommittedDeckTemplatesAreUpToDate) {
  const fs::path shapes = fs::path(RICOCHET_SOURCE_DIR) / "liggghts-inputs/impact/shapes";
  const fs::path tmp = fs::temp_directory_path() / ("dem-shapes-" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  for (const char* name : {"cylinder", "triangle"})
    for (const char* mode : {"slab", "box"}) {
      const Shape s = Shape::resolve(name);
      TemplateOptions o;
      o.full_section_at_ends = std::string(mode) == "slab";
      const auto t = make_sphere_template(s, o.full_section_at_ends ? 0.10 : s.length_m, o);
      const std::string base = std::string(name) + "_" + mode;
      write_sphere_file(t, (tmp / (base + ".ms")).string());
      write_template_include(t, "${deck_dir}/shapes/" + base + ".ms",
                             (tmp / (base + ".in")).string());
      EXPECT_EQ(read(tmp / (base + ".ms")), read(shapes / (base + ".ms"))) << base;
      EXPECT_EQ(read(tmp / (base + ".in")), read(shapes / (base + ".in"))) << base;
    }
  fs::remove_all(tmp);
}

}  // namespace
