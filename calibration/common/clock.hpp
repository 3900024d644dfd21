// Wall time for the `seconds` every result reports (one definition; issue 34).
#pragma once

#include <chrono>

namespace ricochet {

/// Seconds [s] of wall time since t0, on the steady clock.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace ricochet
