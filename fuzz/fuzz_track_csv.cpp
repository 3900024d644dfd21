// libFuzzer target for the track CSV reader, kinematics::parse_track_csv (see fuzz/README.md).
//
// Every input is read twice: without a pixel size, and with 0.5 mm/px and image y down (the
// options of `ricochet reconstruct`). Properties checked:
//  1. the reader either returns a track or throws InputError naming the file; any other
//     exception, crash, leak, hang or sanitizer report is a bug;
//  2. an accepted track is one the reconstruction can take: at least 6 rows, t, x, y and theta
//     of equal lengths and finite, t strictly increasing, mark radius finite and >= 0.
// There is no track writer, so there is no round trip to check.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>

#include "common/error.hpp"
#include "fuzz_common.hpp"
#include "kinematics/reconstruct.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_track_csv", what, detail);
}

void check(const std::string& text, std::optional<double> pixel_size, bool y_down) {
  namespace k = ricochet::kinematics;
  k::Track tr;
  try {
    tr = k::parse_track_csv(text, "fuzz-track.csv", pixel_size, y_down);
  } catch (const ricochet::InputError& e) {
    if (e.file() != "fuzz-track.csv") fail("InputError names the wrong file:", e.what());
    return;
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }
  const std::size_t n = tr.t.size();
  if (n < 6 || tr.x.size() != n || tr.y.size() != n || tr.theta.size() != n)
    fail("accepted a track with too few rows or ragged columns");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(tr.t[i]) || !std::isfinite(tr.x[i]) || !std::isfinite(tr.y[i]) ||
        !std::isfinite(tr.theta[i]))
      fail("accepted a non-finite value at row", std::to_string(i));
    if (i > 0 && !(tr.t[i] > tr.t[i - 1])) fail("accepted a non-increasing time");
  }
  if (!std::isfinite(tr.mark_radius_m) || tr.mark_radius_m < 0) fail("bad mark radius");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  check(text, std::nullopt, false);
  check(text, 0.5e-3, true);
  return 0;
}
