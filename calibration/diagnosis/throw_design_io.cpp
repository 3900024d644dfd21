// The design of throws as JSON and as a plan file (throw_design.hpp; docs/commands/design.md).
#include <fmt/format.h>

#include <cmath>

#include "common/csv.hpp"
#include "common/json_number.hpp"
#include "diagnosis/throw_design.hpp"

namespace ricochet::diagnosis {
namespace {

nlohmann::json to_json(const PairOnDesign& p) {
  return {{"lambda", finite_or_null(p.lambda)},
          {"lambda_ab", finite_or_null(p.lambda_ab)},
          {"lambda_ba", finite_or_null(p.lambda_ba)},
          {"power", finite_or_null(p.power)}};
}

nlohmann::json states_json(const std::vector<Vel3>& states, const char* prefix) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < states.size(); ++i)
    out.push_back({{"id", fmt::format("{}{:03d}", prefix, i + 1)},
                   {"vin_x", states[i][kVx]},
                   {"vin_y", states[i][kVy]},
                   {"win", states[i][kW]}});
  return out;
}

}  // namespace

nlohmann::json to_json(const ThrowDesign& d) {
  nlohmann::json rivals = nlohmann::json::array();
  for (const Rival& r : d.rivals) {
    nlohmann::json params = nlohmann::json::object();
    for (std::size_t i : r.model.calibrated_indices())
      params[r.model.spec(i).name] = r.model.values()[i];
    rivals.push_back({{"name", r.name},
                      {"effects", r.effects},
                      {"law", r.law},
                      {"calibrated", params},
                      {"error", finite_or_null(r.error)}});
  }
  nlohmann::json pairs = nlohmann::json::array();
  for (const PairResult& p : d.pairs)
    pairs.push_back({{"a", d.rivals[p.a].name},
                     {"b", d.rivals[p.b].name},
                     {"nested", p.nested},
                     {"indistinguishable", p.indistinguishable},
                     {"beyond_budget", p.beyond_budget},
                     {"alone", p.indistinguishable ? nlohmann::json(nullptr) : to_json(p.alone)},
                     {"plan", to_json(p.plan)},
                     {"uniform", to_json(p.uniform)},
                     {"set", to_json(p.set)}});
  nlohmann::json observables = nlohmann::json::array();
  for (int k = 0; k < kObservables; ++k)
    if (d.use[k]) observables.push_back(kObservableNames[k]);
  return {
      {"shape", d.shape},
      {"releases", d.releases},
      {"budget", d.plan.size()},
      {"candidates", d.candidates},
      {"excluded_candidates", d.excluded},
      {"alpha", d.alpha},
      {"test_level", d.test_level},
      {"seed", d.seed},
      {"observables", observables},
      {"box", {{"vin_x", d.box.vin_x}, {"vin_y", d.box.vin_y}, {"win", d.box.win}}},
      {"rivals", rivals},
      {"pairs", pairs},
      {"min_pair",
       {{"plan", to_json(d.min_plan)},
        {"uniform", to_json(d.min_uniform)},
        {"set", to_json(d.min_set)}}},
      {"greedy_lambda", finite_or_null(d.greedy_lambda)},
      {"exchange", {{"passes", d.passes}, {"swaps", d.swaps}}},
      {"plan", states_json(d.plan, "D")},
      {"uniform", states_json(d.uniform, "U")},
      {"seconds",
       {{"calibration", d.calibration_s},
        {"prediction", d.prediction_s},
        {"selection", d.selection_s},
        {"total", d.seconds}}},
  };
}

void write_plan_csv(const ThrowDesign& d, const std::string& path,
                    const std::vector<std::string>& comments, const std::string& option) {
  CsvTable t;
  for (const auto& c : comments) t.comment(c);
  t.row({"id", "shape", "vin_x[m/s]", "vin_y[m/s]", "win[rad/s]"});
  for (std::size_t i = 0; i < d.plan.size(); ++i)
    t.row({fmt::format("D{:03d}", i + 1), d.shape, CsvTable::num(d.plan[i][kVx]),
           CsvTable::num(d.plan[i][kVy]), CsvTable::num(d.plan[i][kW])});
  t.write(path, option);
}

}  // namespace ricochet::diagnosis
