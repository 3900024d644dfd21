#include "stats/campaign_outcomes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/h5.hpp"
#include "common/json_number.hpp"
#include "impact/block_track.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::stats {

bool is_numerical_failure(const std::string& status) {
  return status == "invalid" || status == "lost_atoms" || status == "extraction_failed" ||
         status == "crashed";
}

bool is_capture(const std::string& status) {
  return status == "timeout" || status == "no_rebound";
}

CampaignOutcomes campaign_outcomes(const std::string& path, const ImpactSet& impacts,
                                   const std::string& where, const std::string& option) {
  CampaignOutcomes o;
  o.source = path;
  o.where = where;
  if (!h5::is_hdf5(path)) return o;
  const h5::File f(path, h5::File::Mode::kRead);
  if (!f.exists("/dem/index/status")) return o;
  const auto ids = f.read_strings("/dem/index/id");
  const auto statuses = f.read_strings("/dem/index/status");
  const auto shapes = f.read_strings("/dem/index/shape");
  const auto params = f.read_strings("/dem/index/params");
  // The filter reads impacts: each index row becomes one, with what its spec records (the
  // reflected velocities of a rebound come from /impacts, which holds only rebounds).
  ImpactSet rows;
  rows.source = path;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::map<std::string, const Impact*> rebounds;
  for (const auto& im : impacts.impacts) rebounds[im.id] = &im;
  for (std::size_t i = 0; i < ids.size() && i < statuses.size(); ++i) {
    Impact im;
    im.id = ids[i];
    im.shape = i < shapes.size() ? shapes[i] : "";
    im.vin = {nan, nan, nan};
    im.vout = {nan, nan, nan};
    if (const auto it = rebounds.find(ids[i]); it != rebounds.end() && statuses[i] == "rebound") {
      im = *it->second;
    } else if (i < params.size()) {
      const auto spec = nlohmann::json::parse(params[i], nullptr, false);
      if (spec.is_object() && spec.contains("vin") && spec["vin"].is_array() &&
          spec["vin"].size() == 3)
        for (int c = 0; c < 3; ++c) im.vin[c] = spec["vin"][c].get<double>();
    }
    rows.impacts.push_back(im);
  }
  const ImpactSet kept = filter(rows, where, option);
  std::map<std::string, std::string> status_of;
  for (std::size_t i = 0; i < ids.size() && i < statuses.size(); ++i)
    status_of[ids[i]] = statuses[i];
  const std::vector<std::string> tracked = block_track_ids(path);
  for (const auto& im : kept.impacts) {
    const std::string& s = status_of[im.id];
    ++o.by_status[s];
    ++o.impacts;
    if (is_numerical_failure(s)) continue;
    ++o.ran;
    if (!is_capture(s)) continue;
    ++o.captured;
    // Where it ends, when the file keeps its track.
    if (std::find(tracked.begin(), tracked.end(), im.id) == tracked.end()) continue;
    const BlockTrack track = read_block_track(path, im.id);
    if (track.size() == 0) continue;
    const std::size_t last = track.size() - 1;
    CapturedEnd e;
    e.id = im.id;
    e.status = s;
    e.t_s = track.t[last];
    e.speed_mps = std::hypot(track.vx[last], track.vy[last]);
    e.spin_radps = track.w[last];
    e.penetration_m = track.penetration[last];
    e.ke_block_J = track.ke_block[last];
    o.captured_ends.push_back(e);
  }
  o.capture = clopper_pearson(o.captured, o.ran);
  return o;
}

nlohmann::json to_json(const CampaignOutcomes& o) {
  nlohmann::json ends = nlohmann::json::array();
  for (const auto& e : o.captured_ends)
    ends.push_back({{"id", e.id},
                    {"status", e.status},
                    {"t", finite_or_null(e.t_s)},
                    {"speed", finite_or_null(e.speed_mps)},
                    {"spin", finite_or_null(e.spin_radps)},
                    {"penetration", finite_or_null(e.penetration_m)},
                    {"ke_block", finite_or_null(e.ke_block_J)}});
  return {{"impacts", o.impacts},
          {"by_status", o.by_status},
          {"ran", o.ran},
          {"captured", o.captured},
          {"capture", {{"rate", o.capture.rate}, {"lo", o.capture.lo}, {"hi", o.capture.hi}}},
          {"interval", "Clopper-Pearson 95 %"},
          {"captured_ends", ends}};
}

std::string format_text(const CampaignOutcomes& o) {
  std::string s = fmt::format("Outcomes (/dem/index): {} impact(s){}\n", o.impacts,
                              o.where.empty() ? "" : " matching " + o.where);
  std::string counts;
  for (const auto& [status, n] : o.by_status)
    counts += fmt::format("{}{} {}", counts.empty() ? "  " : ", ", status, n);
  s += counts + "\n";
  s += fmt::format(
      "  captured (timeout or no_rebound): {} of the {} that ran (invalid, lost_atoms, "
      "extraction_failed and crashed apart): {:.3f}, 95 % Clopper-Pearson [{:.3f}, {:.3f}]\n",
      o.captured, o.ran, o.capture.rate, o.capture.lo, o.capture.hi);
  if (!o.captured_ends.empty())
    s += "  where the captured tracks end (last record; lowest point below the level, < 0 "
         "above):\n";
  for (const auto& e : o.captured_ends)
    s += fmt::format(
        "    {} ({}): t = {:.3f} s, |v| = {:.3f} m/s, omega = {:.2f} rad/s, lowest point {:.1f} "
        "mm, block kinetic energy {:.3g} J\n",
        e.id, e.status, e.t_s, e.speed_mps, e.spin_radps, e.penetration_m * 1e3, e.ke_block_J);
  return s;
}

}  // namespace ricochet::stats
