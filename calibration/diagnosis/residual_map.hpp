// Where along the contact the law fails (issue 33): the residual force of measured histories
// (measured minus law, diagnosis/force_residual.hpp) averaged by branch (loading: the
// penetration grows; unloading) and by depth band (h over the release's deepest h: [0, 1/3),
// [1/3, 2/3), [2/3, 1]). The discovery's library names a force of a given shape; the map shows
// the residual's shape whatever it is, so that a user reads which part of the cycle a law misses
// before choosing an effect (a bed yielding on loading, a stiffer unloading, a drag at depth).
// Each release counts once in a cell (its mean over its samples there), so the standard error is
// over releases, as the discovery's bootstrap.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "diagnosis/force_law.hpp"

namespace ricochet::diagnosis {

/// One cell of the map: per component (normal, tangential [N], moment [N m]) the mean over its
/// releases of each release's mean residual there, its standard error over releases (NaN below
/// two releases), and the counts.
struct ResidualCell {
  std::array<double, kForceComponents> mean{}, se{};
  std::size_t releases = 0, samples = 0;
};

struct ResidualMap {
  static constexpr std::size_t kBands = 3;  ///< depth bands of h / h_max
  /// cell[branch][band], branch 0 loading, 1 unloading.
  std::array<std::array<ResidualCell, kBands>, 2> cell{};
};

/// The map of `residuals` (force_residual's samples and residuals). A sample's band is its h over
/// the largest h of its release; a release without contact samples adds nothing.
ResidualMap residual_map(std::span<const ReleaseResidual> residuals);

/// {"loading": [band0, band1, band2], "unloading": [...]}, each band {"h_over_hmax": [lo, hi],
/// "releases", "samples", "mean": {"normal", "tangential", "moment"}, "se": {...}}.
nlohmann::json to_json(const ResidualMap& map);

/// The table of the map: one row per branch and component (normal, tangential [N]; moment
/// [N m]), cells "mean +- se" per depth band, "-" for an empty or unmeasured cell. The text and
/// the report print it.
std::vector<std::string> residual_map_header();
std::vector<std::vector<std::string>> residual_map_rows(const ResidualMap& map);

/// residual_map_rows as aligned text, under a one-line title.
std::string format_text(const ResidualMap& map);

}  // namespace ricochet::diagnosis
