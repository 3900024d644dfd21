#include "campaign_schedule.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <stdexcept>

#include "bed.hpp"
#include "file_lock.hpp"

namespace ricochet::dem {

std::vector<int> schedule_order(const std::vector<std::string>& bed_keys,
                                const std::vector<char>& cached, int groups) {
  std::vector<int> order;
  const int n = static_cast<int>(bed_keys.size());
  if (groups == 1) {
    for (int i = 0; i < n; ++i) order.push_back(i);
    return order;
  }
  std::vector<std::string> beds;  // in the order of their first pending impact
  for (const auto& k : bed_keys)
    if (std::find(beds.begin(), beds.end(), k) == beds.end()) beds.push_back(k);
  const auto cached_bed = [&](const std::string& key) {
    for (int i = 0; i < n; ++i)
      if (bed_keys[static_cast<std::size_t>(i)] == key)
        return cached[static_cast<std::size_t>(i)] != 0;
    return false;
  };
  for (const bool first_pass : {true, false})
    for (const auto& key : beds) {
      if (cached_bed(key) != first_pass) continue;
      for (int i = 0; i < n; ++i)
        if (bed_keys[static_cast<std::size_t>(i)] == key) order.push_back(i);
    }
  return order;
}

int claim_next(const std::string& claims_path, const std::vector<int>& order,
               const std::vector<std::string>& bed_keys, const std::string& cache_dir,
               bool* waits) {
  const FileLock lock(claims_path);
  std::set<int> claimed;
  {
    std::ifstream in(claims_path);
    for (int c; in >> c;) claimed.insert(c);
  }
  std::set<std::string> taken;  // beds that a claim of another group builds or waits for
  for (int c : claimed) {
    const std::string& key = bed_keys.at(static_cast<std::size_t>(c));
    if (!bed_cached(cache_dir, key)) taken.insert(key);
  }
  int pick = -1, unbuilt = -1, waiting = -1;
  if (waits) *waits = false;
  for (int i : order) {
    if (claimed.count(i)) continue;
    const std::string& key = bed_keys.at(static_cast<std::size_t>(i));
    if (bed_cached(cache_dir, key)) {
      pick = i;
      break;
    }
    if (unbuilt < 0 && !taken.count(key) && !bed_building(cache_dir, key)) unbuilt = i;
    if (waiting < 0) waiting = i;
  }
  if (pick < 0) {
    pick = unbuilt >= 0 ? unbuilt : waiting;
    if (waits) *waits = pick >= 0 && unbuilt < 0;
  }
  if (pick >= 0) {
    std::ofstream out(claims_path, std::ios::app);
    out << pick << "\n";
    if (!out.flush())
      throw std::runtime_error("campaign claims file " + claims_path + ": cannot write");
  }
  return pick;
}

}  // namespace ricochet::dem
