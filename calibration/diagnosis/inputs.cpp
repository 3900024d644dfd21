#include "diagnosis/inputs.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "common/error.hpp"
#include "fit/fit.hpp"

namespace ricochet::diagnosis {

DiagnoseOptions make_options(const OptionValues& v) {
  DiagnoseOptions o;
  o.assess.folds = parse_folds(v.folds);
  o.assess.fit.seed = v.seed;
  o.assess.fit.threads = v.threads;
  o.assess.fit.engine.dt_s = v.dt_s;
  o.alpha = v.alpha;
  o.assess.repeats = v.repeats;
  o.screen = v.screen;
  o.adequate_z = v.adequate_z;
  o.pairs = !v.no_pairs;
  o.candidates = v.candidates;
  o.assess.release_fits = !v.no_release_fits;
  o.assess.release_intervals = !v.no_intervals;
  o.assess.use_features = !v.no_features;
  if (v.orientations != 0) o.assess.fit.alpha.marginal_points = v.orientations;
  o.assess.fit.alpha.polish_points = v.polish_orientations;
  o.assess.marginal_starts = v.orientation_starts;
  o.assess.fit.alpha.search_xtol = v.search_xtol;
  try {
    o.assess.fit.alpha.search = fit::orientation_search_from(v.orientation_search);
  } catch (const std::invalid_argument& e) {
    throw InputError("<command line>", 0, "--orientation-search", e.what());
  }
  if (v.error == "set-mean")
    o.assess.scale = ErrorScale::kSetMean;
  else if (v.error == "eq7")
    o.assess.scale = ErrorScale::kEq7;
  else
    throw InputError("<command line>", 0, "--error",
                     "'" + v.error + "': use set-mean (default) or eq7 (the paper's denominators)");
  return o;
}

std::vector<std::string> shapes_to_analyse(const ImpactSet& set, const std::string& shape_name) {
  if (!shape_name.empty()) return {shape_name};
  std::vector<std::string> shapes;
  for (const auto& im : set.impacts)
    if (std::find(shapes.begin(), shapes.end(), im.shape) == shapes.end())
      shapes.push_back(im.shape);
  return shapes;
}

Inputs select_inputs(const ImpactSet& set, const std::string& shape_name, const std::string& data) {
  Inputs in;
  try {
    in.shape = Shape::resolve(shape_name);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("<command line>", 0, "--shape", e.what());
  }
  in.set = fit::select_shape(set, in.shape);
  if (in.set.size() < 4)
    throw InputError(data, 0, "shape",
                     "only " + std::to_string(in.set.size()) + " release(s) of shape '" +
                         in.shape.name + "': the held-out error needs at least 4");
  return in;
}

Inputs load_inputs(const std::string& data, const std::string& shape_name,
                   const std::string& where) {
  ImpactSet all = read_impact_set(data);
  if (all.empty()) throw InputError(data, 0, "id", "the impact set has no release");
  all = filter_nonempty(all, where, data);
  const std::vector<std::string> shapes = shapes_to_analyse(all, shape_name);
  if (shapes.size() > 1) {
    std::string list;
    for (const auto& s : shapes) list += (list.empty() ? "" : ", ") + s;
    throw InputError("<command line>", 0, "--shape",
                     "the data hold several shapes (" + list + "): choose one with --shape");
  }
  return select_inputs(all, shapes.front(), data);
}

ReplicateScatter borrowed_scatter(const std::string& path, const std::string& shape,
                                  const std::string& option, const std::string& where,
                                  const std::string& where_option) {
  const ImpactSet chosen = filter_nonempty(read_impact_set(path), where, path, where_option);
  ReplicateScatter r = replicate_scatter(select_inputs(chosen, shape, path).set);
  if (r.groups < 2)
    throw InputError(
        path, 0, option,
        fmt::format("{} replicate group(s) of shape {}{}: the pooled scatter needs "
                    "at least 2 (releases sharing a replicate label or an incident "
                    "state)",
                    r.groups, shape, where.empty() ? "" : " matching '" + where + "'"));
  r.source = path;
  r.where = where;
  return r;
}

void borrow_floor(DiagnoseOptions& options, const OptionValues& values, const Inputs& inputs) {
  if (values.floor_replicates.empty()) return;
  options.assess.borrowed_floor =
      borrowed_scatter(values.floor_replicates, inputs.shape.name, "--floor-replicates",
                       values.floor_where, "--floor-where");
}

std::optional<ForceHistoryScatter> force_history_floor(
    const ImpactSet& set, const Shape& shape,
    const std::vector<std::optional<MeasuredHistory>>& histories,
    const std::optional<ReplicateScatter>& borrowed) {
  ForceHistoryScatter own = force_history_scatter(set, histories, shape);
  if (own.groups > 0) return own;
  if (!borrowed) return std::nullopt;
  const std::string& path = borrowed->source;
  const ImpactSet other =
      select_inputs(filter(read_impact_set(path), borrowed->where), shape.name, path).set;
  ForceHistoryScatter scatter =
      force_history_scatter(other, measured_histories(path, other, shape), shape);
  if (scatter.groups == 0) return std::nullopt;
  scatter.source = path;
  scatter.where = borrowed->where;
  return scatter;
}

}  // namespace ricochet::diagnosis
