// Shared helpers of the libFuzzer targets (see fuzz/README.md): failing with a message, and
// bit-exact comparison of impact sets for the round-trip checks.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>

#include "impact/impact_set.hpp"

namespace ricochet::fuzz {

/// A property of the target does not hold: report and abort, so libFuzzer saves the input.
[[noreturn]] inline void fail(const char* target, const char* what,
                              const std::string& detail = {}) {
  std::fprintf(stderr, "%s: %s %s\n", target, what, detail.c_str());
  std::abort();
}

inline bool same(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
inline bool same(const Vel3& a, const Vel3& b) {
  return same(a[0], b[0]) && same(a[1], b[1]) && same(a[2], b[2]);
}
inline bool same(const std::optional<double>& a, const std::optional<double>& b) {
  return a.has_value() == b.has_value() && (!a || same(*a, *b));
}
inline bool same(const std::optional<Vel3>& a, const std::optional<Vel3>& b) {
  return a.has_value() == b.has_value() && (!a || same(*a, *b));
}

/// Same impacts, comments and extra columns, doubles compared bit for bit (source not compared).
inline bool same_set(const ImpactSet& a, const ImpactSet& b) {
  if (a.comments != b.comments || a.extra_names != b.extra_names ||
      a.extra_units != b.extra_units || a.size() != b.size())
    return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto& x = a.impacts[i];
    const auto& y = b.impacts[i];
    if (x.id != y.id || x.shape != y.shape || x.op != y.op || x.replicate != y.replicate ||
        !same(x.vin, y.vin) || !same(x.vout, y.vout) || !same(x.alpha_in, y.alpha_in) ||
        !same(x.penetration, y.penetration) || !same(x.contact_duration, y.contact_duration) ||
        !same(x.weight, y.weight) || !same(x.sigma_vin, y.sigma_vin) ||
        !same(x.sigma_vout, y.sigma_vout) || x.extra.size() != y.extra.size())
      return false;
    for (std::size_t k = 0; k < x.extra.size(); ++k)
      if (!same(x.extra[k], y.extra[k])) return false;
  }
  return true;
}

/// The HDF5 targets' two temporary files (the reader opens files by name, like every command):
/// the input and the round trip, one pair per process, in $RICOCHET_FUZZ_TMPDIR (the bench gives
/// each run its own folder and removes it, so that inputs a crash interrupts are not left
/// behind), else /dev/shm, else the temporary folder.
inline std::string temp_h5_name(const std::string& target, const char* tag) {
  namespace fs = std::filesystem;
  const char* env = std::getenv("RICOCHET_FUZZ_TMPDIR");
  const fs::path dir = env && *env                    ? fs::path(env)
                       : fs::is_directory("/dev/shm") ? fs::path("/dev/shm")
                                                      : fs::temp_directory_path();
  return (dir / (target + "-" + std::to_string(::getpid()) + "-" + tag + ".h5")).string();
}

/// The pair of temporary files of one HDF5 target (the input as written, and its round trip),
/// named once per process; remove() deletes both (after every input and at exit).
struct TempH5Files {
  explicit TempH5Files(const std::string& target)
      : input(temp_h5_name(target, "in")), roundtrip(temp_h5_name(target, "rt")) {}
  void remove() const {
    std::remove(input.c_str());
    std::remove(roundtrip.c_str());
  }
  std::string input, roundtrip;
};

}  // namespace ricochet::fuzz
