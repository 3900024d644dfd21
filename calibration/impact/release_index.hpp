// Which measured release a campaign impact was run at, matched by id: the one place the rule is
// written (stats::paired_residuals pairs a campaign with the lab by it; `report --against`
// compares a campaign run at lab releases with those releases).
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>

#include "impact/impact_set.hpp"

namespace ricochet {

/// The releases of a measured set, by id.
class ReleaseIndex {
 public:
  explicit ReleaseIndex(const ImpactSet& releases) {
    for (std::size_t i = 0; i < releases.size(); ++i) index_[releases.impacts[i].id] = i;
  }

  /// The release (index into the set) that impact `id` was run at: the release with that id,
  /// else the one whose id is the longest prefix of `id` ending before a '-' (a campaign's
  /// "C02-x_impact_frac0.26" or "C02-s1" was run at release C02); nullopt when none.
  std::optional<std::size_t> find(const std::string& id) const {
    auto it = index_.find(id);
    for (auto dash = id.rfind('-'); it == index_.end() && dash != std::string::npos && dash > 0;
         dash = id.rfind('-', dash - 1))
      it = index_.find(id.substr(0, dash));
    if (it == index_.end()) return std::nullopt;
    return it->second;
  }

 private:
  std::map<std::string, std::size_t> index_;
};

}  // namespace ricochet
