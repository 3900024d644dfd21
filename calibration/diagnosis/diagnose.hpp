// Compare a model with an impact set, diagnose which effect of the catalog is missing, and climb
// the ladder of models (issue 6). Every calibration is done by the fit module (fit/fit.hpp)
// through assess() (diagnosis/assess.hpp); this file only judges.
//
// compare():  the model calibrated on the set (population and per release), the noise floor,
//             errors per observable, per release and per regime (thirds of |V_in|), residual
//             and parameter trends against impact features, measured-vs-predicted KS tests.
// diagnose(): every registered effect not in the model (plugins included) is added at its
//             neutral value (so the new model starts exactly at the calibrated base model),
//             recalibrated, and judged by its held-out error. Ranking key: the penalised held-out
//             error  heldout + p_added * floor / n_train  (the expected held-out cost of fitting
//             p_added useless parameters). An effect is SUPPORTED when its penalised drop
//             exceeds z standard errors of the paired per-release drops:
//               drop - p_added * floor / n_train > z * SE(drop_i),   drop_i = e_i^base - e_i^cand
//             (held-out errors of the same release, so the comparison is paired).
//             Evidence in words combines the drop, the observable whose error falls most, the
//             effect's own signature (a score test: the correlation of the base model's scaled
//             residuals with the change the effect makes to the predictions, both projected off
//             the base parameters' directions) and the residual/parameter trends that the
//             shared notes associate with the effect.
// ladder():   rungs base, base + E1, base + E1 + E2, ... each recalibrated (warm start from the
//             previous rung, the new effect at its neutral value) with in-sample and held-out
//             errors per observable. auto_ladder() picks each next effect by diagnose().
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "diagnosis/assess.hpp"
#include "diagnosis/trends.hpp"
#include "effects/registry.hpp"
#include "stats/stats.hpp"

namespace ricochet::diagnosis {

struct DiagnoseOptions {
  AssessOptions assess;
  TrendOptions trends;
  double z = 2.0;  ///< standard errors a drop must exceed to support an effect
  /// Effects to try; empty = every effect of the registry not in the model.
  std::vector<std::string> candidates;
  /// Registry of effects (built-ins and loaded plugins); nullptr = EffectRegistry::global().
  const EffectRegistry* registry = nullptr;
  /// Probe step of the signature test, as a fraction of the parameter's range from its neutral
  /// value towards the other bound.
  double probe_fraction = 0.1;
  bool progress = true;  ///< progress bar on a terminal
};

/// Errors over a subset of releases (a regime).
struct Regime {
  std::string name;  ///< e.g. "|V_in| in [2.9, 3.3] m/s"
  std::vector<std::size_t> releases;
  MeanSe heldout, floor;
};

/// The result of compare().
struct Baseline {
  Assessment base;
  NoiseFloor floor;
  Adequacy adequacy;
  std::vector<fit::ReleaseFit> release_fits;  ///< empty when options.assess.release_fits is off
  std::vector<Feature> features;
  std::vector<Trend> residual_trends;   ///< held-out residuals
  std::vector<Trend> parameter_trends;  ///< per-release calibrated parameters
  std::vector<Regime> regimes;
  /// Two-sample KS test of the measured against the held-out predicted values, per observable.
  std::array<stats::KsResult, kObservables> ks{};
  /// Floors of the error denominators actually used (m/s, m/s, rad/s, m, s; AssessOptions::scale).
  Obs error_floors{};
  double seconds = 0;
};
Baseline compare(const Model& model, const Shape& shape, const ImpactSet& set,
                 const DiagnoseOptions& options);

/// One candidate effect, judged.
struct Candidate {
  std::string effect;
  std::string meaning;                        ///< what the effect stands for, in words
  std::vector<std::string> added_parameters;  ///< its calibrated parameters
  std::vector<double> added_values;           ///< their population-fit values
  Assessment assessment;                      ///< base + effect, recalibrated
  Adequacy adequacy;                          ///< of base + effect against the noise floor
  double heldout_error = 0, heldout_se = 0;
  double error_drop = 0, drop_se = 0;  ///< base - candidate held-out error, paired SE
  double penalty = 0;                  ///< p_added * floor / n_train
  double penalised_heldout = 0;        ///< ranking key
  bool supported = false;
  double signature_r = NAN;  ///< score-test correlation (see file comment)
  std::string evidence;      ///< words with numbers
  std::string error;         ///< non-empty when the effect could not be tried
};

struct Diagnosis {
  Baseline baseline;
  std::string verdict;                   ///< "adequate" | "missing physics"
  std::vector<Candidate> ranking;        ///< best first
  std::string summary;                   ///< one or two sentences
  std::vector<std::string> unexplained;  ///< residual structure left after the best candidate
  double seconds = 0;
};
Diagnosis diagnose(const Model& model, const Shape& shape, const ImpactSet& set,
                   const DiagnoseOptions& options);
/// Same, reusing a compare() result of the same model, shape, set and options.
Diagnosis diagnose(Baseline baseline, const Model& model, const Shape& shape, const ImpactSet& set,
                   const DiagnoseOptions& options);

/// One rung of a ladder.
struct Rung {
  std::vector<std::string> effects;
  std::string added;  ///< empty for the base rung
  Assessment assessment;
  Adequacy adequacy;
};
struct Ladder {
  NoiseFloor floor;  ///< computed with the base rung's calibrated model
  std::vector<Rung> rungs;
  std::vector<Diagnosis> rounds;  ///< auto_ladder(): the diagnosis that chose each rung
  std::string stop_reason;        ///< auto_ladder(): why it stopped
};
/// Rungs: model, model + adds[0], model + adds[0] + adds[1], ...
Ladder ladder(const Model& model, const Shape& shape, const ImpactSet& set,
              const std::vector<std::string>& adds, const DiagnoseOptions& options);
/// Rounds of diagnose(): adds the best supported effect until the model is adequate, no effect
/// is supported, or `max_rounds` effects were added.
/// `first`: an existing diagnosis of `model` on `set` (same options) used as round 0.
Ladder auto_ladder(const Model& model, const Shape& shape, const ImpactSet& set, int max_rounds,
                   const DiagnoseOptions& options, const Diagnosis* first = nullptr);

/// The model of a rung, with its calibrated values (to continue from it).
Model with_values(const Model& model, const std::vector<double>& values);

nlohmann::json to_json(const Assessment& a, const NoiseFloor& floor);
nlohmann::json to_json(const Baseline& b, const ImpactSet& set);
nlohmann::json to_json(const Candidate& c, const std::array<bool, kObservables>& use);
/// The `ricochet diagnose --json` document (docs/commands/diagnose.md).
nlohmann::json to_json(const Diagnosis& d);
/// The `ricochet ladder --json` document (docs/commands/ladder.md).
nlohmann::json to_json(const Ladder& l);

}  // namespace ricochet::diagnosis
