// A double as JSON: the number, or null where it is not finite. JSON has no NaN or infinity, and
// every result file writes an undefined value (a fit that did not run, an interval with one
// sample, a p-value of an empty test) the same way, so that a reader tests for null alone.
#pragma once

#include <cmath>

#include <nlohmann/json.hpp>

namespace ricochet {

inline nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace ricochet
