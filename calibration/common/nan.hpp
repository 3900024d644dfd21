// The quiet NaN that marks a missing or undefined value (an empty sample's mean, a column a file
// does not hold, a fit that did not run), written once for every file that returns or stores one.
#pragma once

#include <limits>

namespace ricochet {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace ricochet
