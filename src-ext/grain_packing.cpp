#include "grain_packing.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "bed.hpp"
#include "campaign_store.hpp"
#include "common/error.hpp"
#include "grain_surrogate.hpp"

namespace ricochet::dem {

namespace {

// A bed's geometry for the grain-count estimate: every bed.* value of impact `id` that is not a
// surrogate input (the box, depth, grain sizes, stiffness...), the seed aside.
std::string bed_geometry(const std::map<std::string, std::map<std::string, std::string>>& grain,
                         const std::string& id, const std::vector<std::string>& inputs) {
  std::string g;
  const auto it = grain.find(id);
  if (it == grain.end()) return g;
  for (const auto& [k, v] : it->second)
    if (k.rfind("bed.", 0) == 0 && k != "bed.seed" &&
        std::find(inputs.begin(), inputs.end(), k) == inputs.end())
      g += (g.empty() ? "" : " ") + k + "=" + v;
  return g;
}

}  // namespace

void measure_points_packing(
    GrainCalibrationResult& r, const std::string& campaign_h5,
    const std::vector<CampaignEntry>& index, const std::string& cache, bool from_grain_count,
    const std::map<std::string, std::map<std::string, std::string>>& grain) {
  const auto& names = campaign_value_names();
  const std::size_t grains_col = std::find(names.begin(), names.end(), "grains") - names.begin();
  std::map<std::string, std::string> bed_of, geometry_of;
  std::map<std::string, long> grains_of;
  for (const auto& e : index) {
    bed_of[e.id] = e.bed_key;
    if (e.bed_key.empty() || geometry_of.count(e.bed_key)) continue;
    geometry_of[e.bed_key] = bed_geometry(grain, e.id, r.parameters);
    if (grains_col < e.values.size() && std::isfinite(e.values[grains_col]))
      grains_of[e.bed_key] = std::lround(e.values[grains_col]);
  }
  const auto recorded = read_bed_packings(campaign_h5);
  std::map<std::string, std::pair<double, std::string>> phi_of;  // key -> value, source
  for (const auto& [key, packing] : recorded) phi_of[key] = {packing.solid_fraction, "recorded"};
  // By geometry: the estimator (built once, on the geometry's recorded beds) and what it estimated.
  std::map<std::string, std::pair<GrainCountPacking, GrainCountEstimate>> estimates;
  const auto estimate = [&](const std::string& id, const std::string& key) {
    const std::string& geometry = geometry_of[key];
    auto it = estimates.find(geometry);
    if (it == estimates.end()) {
      std::vector<BedPacking> refs;
      for (const auto& [k, packing] : recorded)
        if (geometry_of.count(k) && geometry_of[k] == geometry) refs.push_back(packing);
      if (refs.empty())
        throw InputError(campaign_h5, 0, "/dem/beds",
                         "impact " + id + ": its bed " + key +
                             " is neither recorded nor cached, and its solid fraction cannot be "
                             "estimated from its grain count: the file records no bed of its "
                             "geometry (" +
                             geometry + ")");
      const GrainCountPacking g = grain_count_packing(refs);
      it = estimates
               .emplace(geometry,
                        std::pair{g, GrainCountEstimate{geometry, {}, g.references, g.loo_max_abs}})
               .first;
    }
    if (!grains_of.count(key))
      throw InputError(campaign_h5, 0, "/dem/index/values",
                       "impact " + id + ": its bed " + key +
                           " is neither recorded nor cached, and its solid fraction cannot be "
                           "estimated from its grain count: its index row has no grain count");
    it->second.second.beds.push_back(key);
    return it->second.first.solid_fraction(grains_of[key]);
  };
  for (auto& p : r.points) {
    double sum = 0;
    std::set<std::string> sources;
    for (const auto& id : p.ids) {
      const std::string& key = bed_of[id];
      const std::string prefix = bed_prefix(cache, key);
      auto it = phi_of.find(key);
      if (it == phi_of.end()) {
        const bool cached =
            !cache.empty() && !key.empty() && std::filesystem::exists(prefix + ".params");
        if (!cached && !(from_grain_count && !key.empty()))
          throw InputError(campaign_h5, 0, "/dem/index/bed_key",
                           "impact " + id + ": its bed " + (key.empty() ? "(no key)" : key) +
                               " is neither recorded in the file (/dem/beds) nor in the bed "
                               "cache " +
                               (cache.empty() ? std::string("(no --bed-cache given)")
                                              : cache + " (--bed-cache)") +
                               ": `ricochet dem campaign DESIGN --out " + campaign_h5 +
                               " --record-beds` records it, --bed-cache measures it, or "
                               "--packing-from-grain-count estimates it");
        std::pair<double, std::string> v;
        if (cached)
          v = {measure_packing(read_bed_files(prefix), MPI_COMM_SELF).solid_fraction, "measured"};
        else
          v = {estimate(id, key), "grain count"};
        it = phi_of.emplace(key, std::move(v)).first;
      }
      sum += it->second.first;
      sources.insert(it->second.second);
    }
    p.solid_fraction = sum / static_cast<double>(p.ids.size());
    for (const auto& src : sources)
      p.solid_fraction_source += (p.solid_fraction_source.empty() ? "" : "+") + src;
  }
  for (auto& [geometry, e] : estimates) r.grain_count_estimates.push_back(std::move(e.second));
}

OT::KrigingResult fit_packing(GrainCalibrationResult& r, const OT::Sample& u) {
  const std::size_t n = r.points.size();
  OT::Sample y(n, 1);
  for (std::size_t i = 0; i < n; ++i) y(i, 0) = r.points[i].solid_fraction;
  OT::KrigingResult model = fit_kriging(u, y, 0.0, nullptr);
  std::vector<double> loo;
  r.solid_fraction_q2 = leave_one_out(u, y, 0.0, model.getCovarianceModel(), loo)[0];
  for (std::size_t i = 0; i < n; ++i) r.points[i].solid_fraction_loo = loo[i];
  return model;
}

}  // namespace ricochet::dem
