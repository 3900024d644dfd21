// libFuzzer target for the impact-set CSV reader (see fuzz/README.md).
//
// Properties checked on every input:
//  1. parse_impact_set_csv either returns a set or throws InputError; any other exception, crash,
//     leak, hang or sanitizer report is a bug.
//  2. A set it accepts survives its own writer: format -> parse gives the same set, and
//     formatting again gives the same text (the CSV round trip is exact).
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "common/error.hpp"
#include "fuzz_common.hpp"
#include "impact/impact_set.hpp"

namespace {
using ricochet::fuzz::same_set;
[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_impact_csv", what, detail);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ricochet::ImpactSet set;
  try {
    set = ricochet::parse_impact_set_csv(text, "fuzz.csv");
  } catch (const ricochet::InputError& e) {
    if (e.file() != "fuzz.csv") fail("InputError names the wrong file:", e.what());
    return 0;  // refused with a located message: the expected outcome for malformed input
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }

  // Accepted input: the writer must reproduce it exactly, and derived views must not crash.
  try {
    const std::string once = ricochet::format_impact_set_csv(set);
    const ricochet::ImpactSet back = ricochet::parse_impact_set_csv(once, "fuzz-roundtrip.csv");
    if (!same_set(set, back)) fail("round trip changed the set:\n", once);
    if (ricochet::format_impact_set_csv(back) != once) fail("writer is not stable:\n", once);
    for (const auto& name : set.feature_names()) (void)set.feature(name);
    (void)ricochet::filter(set, "vin_x<3.5 && shape==triangle && speed_in>=0");
  } catch (const std::exception& e) {
    fail("accepted set fails downstream:", e.what());
  }
  return 0;
}
