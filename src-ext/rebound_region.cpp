#include "rebound_region.hpp"

#include <cmath>

#include "grain_surrogate.hpp"

namespace ricochet::dem {

void tally_rebounds(GrainCalibrationResult& r, const std::vector<CampaignEntry>& index,
                    const std::map<std::string, std::map<std::string, std::string>>& grain) {
  const auto superseded = [&](const std::string& id) {
    const std::string prefix = id + "-Lx";
    for (const auto& e : index)
      if (e.id.rfind(prefix, 0) == 0) return true;
    return false;
  };
  std::map<std::vector<double>, std::size_t> at;
  for (const auto& e : index) {
    const bool rebound = e.status == "rebound";
    const bool missed = e.status == "timeout" || e.status == "no_rebound" ||
                        (e.status == "end_wall" && !superseded(e.id));
    const auto it = grain.find(e.id);
    if ((!rebound && !missed) || it == grain.end()) continue;
    std::vector<double> x;
    for (const auto& p : r.parameters) x.push_back(grain_value(it->second.at(p), r.source, p));
    auto [pos, inserted] = at.emplace(x, r.rebound_points.size());
    if (inserted) r.rebound_points.emplace_back().x = x;
    auto& t = r.rebound_points[pos->second];
    ++t.counted;
    if (rebound)
      ++t.rebounds;
    else
      t.missed.push_back(e.id);
  }
}

std::optional<OT::KrigingResult> fit_rebound_region(GrainCalibrationResult& r) {
  const auto& pts = r.rebound_points;
  const std::size_t n = pts.size(), d = r.parameters.size();
  bool all = true;
  for (const auto& t : pts) all = all && t.rebounds == t.counted;
  if (all) return std::nullopt;
  OT::Sample u(n, d), y(n, 1);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < d; ++k)
      u(i, k) = (pts[i].x[k] - r.lower[k]) / (r.upper[k] - r.lower[k]);
    y(i, 0) = static_cast<double>(pts[i].rebounds) / static_cast<double>(pts[i].counted);
  }
  OT::KrigingResult model = fit_kriging(u, y, 0.0, nullptr);
  std::vector<double> loo;
  leave_one_out(u, y, 0.0, model.getCovarianceModel(), loo);
  std::size_t agree = 0;
  for (std::size_t i = 0; i < n; ++i) {
    r.rebound_points[i].loo = loo[i];
    agree += (loo[i] >= 0.5) == (y(i, 0) >= 0.5);
  }
  r.rebound_loo_agreement = static_cast<double>(agree) / static_cast<double>(n);
  return model;
}

}  // namespace ricochet::dem
