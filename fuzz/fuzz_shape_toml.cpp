// libFuzzer target for the shape TOML reader, Shape::from_toml_string (see fuzz/README.md).
//
// Properties checked on every input:
//  1. the reader either returns a shape or throws InputError naming the file; any other
//     exception, crash, leak, hang or sanitizer report is a bug;
//  2. an accepted shape is one the engine can use: at least one vertex, every coordinate finite,
//     rounding radius, mass and inertia finite and > 0, length finite and >= 0, centroid at the
//     origin, and its derived geometry (bounding radius, depth below centroid) finite.
// There is no shape writer, so there is no round trip to check.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "common/error.hpp"
#include "engine/shape.hpp"
#include "fuzz_common.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_shape_toml", what, detail);
}

bool positive(double v) {
  return std::isfinite(v) && v > 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ricochet::Shape s;
  try {
    s = ricochet::Shape::from_toml_string(text, "fuzz-shape.toml");
  } catch (const ricochet::InputError& e) {
    if (e.file() != "fuzz-shape.toml") fail("InputError names the wrong file:", e.what());
    return 0;
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }
  if (s.vertices.empty()) fail("accepted a shape without vertices");
  for (const auto& v : s.vertices)
    if (!std::isfinite(v[0]) || !std::isfinite(v[1])) fail("accepted a non-finite vertex");
  if (!positive(s.rounding_radius_m) || !positive(s.mass_kg) || !positive(s.inertia_kgm2))
    fail("accepted a non-finite or non-positive radius, mass or inertia");
  if (!std::isfinite(s.length_m) || s.length_m < 0) fail("accepted a bad length_m");
  if (!std::isfinite(s.bounding_radius()) || !std::isfinite(s.depth_below_centroid(0.3)))
    fail("accepted a shape with non-finite geometry");
  return 0;
}
