// Calibration results as JSON (the `ricochet calibrate --json` contract) and HDF5 (the full
// record, written incrementally so that a long run can be killed and resumed).
//
// HDF5 layout (group `/calibration` by default):
//   attributes   schema = "ricochet-calibration-1", shape, data, model_json, model_toml,
//                settings_json (every FitOptions field, seed included), alpha_mode
//   names        all model parameter names (strings); calibrated: the fitted ones
//   impacts/     the input impact set (impact/impact_set.hpp HDF5 form)
//   releases/id  release ids, one per row of releases/rows, in completion order
//   releases/rows  one row per release; column names in the attribute "columns":
//                index, error, threshold, status, evaluations, seconds, alpha_rad,
//                alpha_lo_rad, alpha_hi_rad, alpha_status, vout_meas_{x,y,w}, vout_sim_{x,y,w},
//                then every model parameter value, then per calibrated parameter
//                NAME_lo, NAME_hi, NAME_status (0 identified, 1 lower_bound_only,
//                2 upper_bound_only, 3 not_identified, -1 not computed),
//                then start_error_0..start_error_{starts-1}
//   releases/statements   the identifiability verdicts, one per calibrated parameter per row
//   profiles/<id>/<NAME>  (value, Eq. 7) points of the interval walks, n x 2
//   summary/     written at the end: per parameter mean, std (and population fit if any)
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "fit/fit.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::fit {

/// JSON of one parameter interval: {"lo", "hi", "status", "statement", "value", "bounds"}.
nlohmann::json to_json(const ParameterInterval& interval);
/// JSON of one release (keys documented in docs/commands/calibrate.md): "id", "params"
/// (calibrated parameters), "fixed", "intervals" ({NAME: [lo, hi]}), "identifiability",
/// "statements", "error", "threshold", "vout_measured", "vout_simulated", "status",
/// "alpha_in" (non-disc shapes), "start_errors", "evaluations", "seconds".
nlohmann::json to_json(const ReleaseFit& fit);
/// Per calibrated parameter over releases: mean and std (n - 1) of the point values (as the
/// paper's Table 4), n, the count per identifiability class, and mean/std over the releases
/// where the parameter is identified. Plus "alpha_in" (degrees) when fitted.
nlohmann::json summary_json(const std::vector<ReleaseFit>& fits);
nlohmann::json to_json(const PopulationFit& fit);
/// Every FitOptions field (the run's settings, seed included).
nlohmann::json to_json(const FitOptions& options);

/// One row per release: id, error, threshold, alpha_rad, then per calibrated parameter its value,
/// NAME_lo, NAME_hi and NAME_status (identifiability class name). Releases with no id are skipped.
void write_csv(const std::string& path, const std::vector<ReleaseFit>& fits);

/// Incremental HDF5 writer of per-release results (layout in the file comment).
class ReleaseFitStore {
 public:
  /// Opens `path`. resume = false: the file is replaced. resume = true: an existing file with
  /// the same model, shape, data and settings is continued (its releases are loaded and
  /// reported by done()); different settings throw InputError naming the file and the
  /// attribute that differs.
  ReleaseFitStore(const std::string& path, const Model& model, const Shape& shape,
                  const ImpactSet& set, const FitOptions& options, bool resume,
                  const std::string& group = "calibration");
  ~ReleaseFitStore();
  ReleaseFitStore(const ReleaseFitStore&) = delete;
  ReleaseFitStore& operator=(const ReleaseFitStore&) = delete;

  /// Results already in the file (resume), by id.
  bool done(const std::string& id) const { return done_.count(id) > 0; }
  const std::vector<ReleaseFit>& existing() const { return existing_; }
  /// Appends one release (row, statements, profiles) and flushes the file.
  void append(std::size_t index, const ReleaseFit& fit);
  /// Writes the summary group (and the population fit, if given).
  void write_summary(const std::vector<ReleaseFit>& fits, const PopulationFit* population,
                     double seconds);

 private:
  struct Impl;
  Impl* impl_;
  std::set<std::string> done_;
  std::vector<ReleaseFit> existing_;
};

/// Reads the per-release results of a calibration file (parameter values, intervals with their
/// status and statement, errors, orientation; profiles are not loaded). Throws InputError
/// naming the file when the group is missing or not a calibration.
std::vector<ReleaseFit> read_release_fits(const std::string& path,
                                          const std::string& group = "calibration");

}  // namespace ricochet::fit
