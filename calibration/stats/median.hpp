// The sample median, written once for the library (robust statistics, the reconstruction's noise
// scale). Header-only, so that the readers compiled alone (the fuzz targets) need no library.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "common/nan.hpp"

namespace ricochet::stats {

/// Median of `v` (taken by value: it is reordered): the middle value, or the mean of the two
/// middle values for an even count; NaN for an empty sample. The values must not be NaN.
inline double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

}  // namespace ricochet::stats
