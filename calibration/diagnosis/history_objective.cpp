// The force histories as a calibration target (history_objective.hpp).
#include "diagnosis/history_objective.hpp"

#include <fmt/format.h>

#include <cmath>

#include "common/error.hpp"

namespace ricochet::diagnosis {

double HistoryObjective::operator()(const Model& model, std::span<const double> params,
                                    const ImpactSet& set) const {
  double total = 0;
  for (const Impact& im : set.impacts) {
    const auto it = histories.find(im.id);
    if (it == histories.end()) continue;
    ResidualSquares q;
    q.add(force_residual(it->second, model, shape, params, engine));
    double mean = 0;
    std::size_t used = 0;
    for (std::size_t c = 0; c < kForceComponents; ++c)
      if (q.n[c] > 0 && std::isfinite(floor[c]) && floor[c] > 0) {
        mean += q.sum[c] / static_cast<double>(q.n[c]) / (floor[c] * floor[c]);
        ++used;
      }
    if (used > 0) total += mean / static_cast<double>(used);
  }
  return weight * total;
}

std::shared_ptr<const HistoryObjective> history_objective(
    const ImpactSet& set, const std::vector<std::optional<MeasuredHistory>>& histories,
    const std::array<double, kForceComponents>& floor, double weight, const Shape& shape,
    const EngineOptions& engine, const std::string& option) {
  if (!(std::isfinite(weight) && weight > 0))
    throw InputError("<command line>", 0, option,
                     fmt::format("{} is not a positive weight", weight));
  bool any = false;
  for (double f : floor) any = any || (std::isfinite(f) && f > 0);
  if (!any)
    throw InputError("<command line>", 0, option,
                     "the force histories have no replicate floor to weigh them by (replicate "
                     "histories in DATA, or --floor-replicates FILE with histories)");
  if (histories.size() != set.size())
    throw std::invalid_argument("history_objective: the histories are not aligned with the set");
  auto o = std::make_shared<HistoryObjective>();
  for (std::size_t i = 0; i < set.size(); ++i)
    if (histories[i]) o->histories.emplace(set.impacts[i].id, *histories[i]);
  o->floor = floor;
  o->weight = weight;
  o->shape = shape;
  o->engine = engine;
  return o;
}

}  // namespace ricochet::diagnosis
