// libFuzzer target for the impact-set CSV reader (see fuzz/README.md).
//
// Properties checked on every input:
//  1. parse_impact_set_csv either returns a set or throws InputError; any other exception, crash,
//     leak, hang or sanitizer report is a bug.
//  2. A set it accepts survives its own writer: format -> parse gives the same set, and
//     formatting again gives the same text (the CSV round trip is exact).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "common/error.hpp"
#include "impact/impact_set.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  std::fprintf(stderr, "fuzz_impact_csv: %s %s\n", what, detail.c_str());
  std::abort();
}

bool same(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
bool same(const ricochet::Vel3& a, const ricochet::Vel3& b) {
  return same(a[0], b[0]) && same(a[1], b[1]) && same(a[2], b[2]);
}
bool same(const std::optional<double>& a, const std::optional<double>& b) {
  return a.has_value() == b.has_value() && (!a || same(*a, *b));
}
bool same(const std::optional<ricochet::Vel3>& a, const std::optional<ricochet::Vel3>& b) {
  return a.has_value() == b.has_value() && (!a || same(*a, *b));
}

bool same_set(const ricochet::ImpactSet& a, const ricochet::ImpactSet& b) {
  if (a.comments != b.comments || a.extra_names != b.extra_names ||
      a.extra_units != b.extra_units || a.size() != b.size())
    return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto& x = a.impacts[i];
    const auto& y = b.impacts[i];
    if (x.id != y.id || x.shape != y.shape || x.op != y.op || !same(x.vin, y.vin) ||
        !same(x.vout, y.vout) || !same(x.alpha_in, y.alpha_in) ||
        !same(x.penetration, y.penetration) || !same(x.contact_duration, y.contact_duration) ||
        !same(x.weight, y.weight) || !same(x.sigma_vin, y.sigma_vin) ||
        !same(x.sigma_vout, y.sigma_vout) || x.extra.size() != y.extra.size())
      return false;
    for (std::size_t k = 0; k < x.extra.size(); ++k)
      if (!same(x.extra[k], y.extra[k])) return false;
  }
  return true;
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
