// Monte Carlo and Sobol results as JSON (the `ricochet montecarlo|sobol --json` contracts) and
// HDF5 (full records through common/h5.hpp).
//
// Monte Carlo file, group /montecarlo:
//   attributes  schema = "ricochet-montecarlo-1", shape, model_json, model_toml, settings_json
//               (runs, seed, dt, incident source, orientation range, chunk), inputs_json
//               (each varied parameter's distribution)
//   varied      names of the varied parameters
//   runs        runs x (varied + 8) rows, appended per chunk and flushed: the varied values,
//               vin_x, vin_y, win, alpha_rad, vout_x, vout_y, wout, status; column names in the
//               attribute "run_columns". A killed run resumes after its last complete chunk.
//   comparison  attribute json: KS statistic, p-value and Cramer-von Mises distance per
//               component against the --compare data (when given), written at the end
// Sobol file, group /sobol: attributes schema = "ricochet-sobol-1", shape, model_json,
// model_toml, settings_json, inputs_json; datasets first, first_lo, first_hi, total, total_lo,
// total_hi (outputs x inputs), second, second_lo, second_hi (outputs x inputs x inputs),
// variance, inputs, outputs, design_x (runs x inputs) and design_y (runs x outputs): the
// OpenTURNS pick-freeze design and the model's outputs.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "uq/montecarlo.hpp"
#include "uq/sobol.hpp"

namespace ricochet::uq {

/// {"vx": .., "vy": .., "w": ..} of one quantity of a comparison.
nlohmann::json components_json(const Vel3& v);
/// {NAME: {"distribution": text, "lo": support lower, "hi": support upper}}.
nlohmann::json inputs_json(const std::vector<ParameterInput>& inputs);
/// {"first_order": {OUTPUT: {INPUT: value}}, "second_order": {OUTPUT: {"A-B": value}},
///  "total_order": ..., "intervals": {"first_order": {OUTPUT: {INPUT: [lo, hi]}}, "second_order":
///  ..., "total_order": ...}, "estimator", "base_size", "evaluations", "confidence", "variance",
///  "seconds"}.
nlohmann::json to_json(const SobolResult& result);
/// {"mean": {vx, vy, w}, "std": {vx, vy, w}} of the reflected velocities of a Monte Carlo.
nlohmann::json moments_json(const MonteCarloResult& result);
/// One row per run: the varied parameters, V_in, alpha_in [rad], V_out and the engine status.
void write_runs_csv(const std::string& path, const MonteCarloResult& result);
/// Settings of a Monte Carlo (runs, seed, dt, incident, orientation range, chunk).
nlohmann::json to_json(const MonteCarloOptions& options, const std::string& incident_source);

/// Incremental HDF5 writer of Monte Carlo runs (layout in the file comment).
class MonteCarloStore {
 public:
  /// resume = true continues an existing file written with the same model, shape, settings and
  /// inputs (else InputError naming the differing attribute); resume = false replaces it.
  MonteCarloStore(const std::string& path, const Model& model, const Shape& shape,
                  const std::vector<ParameterInput>& inputs, const MonteCarloOptions& options,
                  const std::string& incident_source, bool resume);
  ~MonteCarloStore();
  MonteCarloStore(const MonteCarloStore&) = delete;
  MonteCarloStore& operator=(const MonteCarloStore&) = delete;

  /// Runs already in the file (complete chunks): the first run to simulate on resume.
  std::size_t done_runs() const { return done_; }
  /// Copies the stored runs [0, done_runs()) into `result` (sized by run_monte_carlo).
  void load(MonteCarloResult& result) const;
  /// Appends runs [begin, end) of `result` and flushes.
  void append(std::size_t begin, std::size_t end, const MonteCarloResult& result);
  /// Writes a JSON document as an attribute of /montecarlo (e.g. "comparison", "range_fit").
  void write_json(const std::string& attribute, const nlohmann::json& doc);

 private:
  struct Impl;
  Impl* impl_;
  std::size_t done_ = 0;
};

/// Writes a Sobol result (layout in the file comment), replacing the file.
void write_sobol_h5(const std::string& path, const SobolResult& result, const Model& model,
                    const Shape& shape, const std::vector<ParameterInput>& inputs,
                    const nlohmann::json& settings);

}  // namespace ricochet::uq
