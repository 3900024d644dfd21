// Options shared by `ricochet compare`, `diagnose`, `ladder` and `report` (docs/commands/*.md):
// they all calibrate a model on an impact set and measure its held-out error, so the options that
// steer that (folds, seed, error denominators, orientations, threads, ...) are declared once here.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "diagnosis/force_history.hpp"
#include "diagnosis/inputs.hpp"
#include "model_options.hpp"

namespace ricochet::cli {

/// Which of the optional diagnosis options a command offers (folds, seed, error, orientations
/// and threads are always there).
struct DiagnosisOptionSet {
  const char* alpha =
      nullptr;  ///< help text of --alpha; nullptr: no --alpha (nor --screen, --no-pairs)
  bool candidates = false;      ///< --candidate
  bool release_fits = false;    ///< --no-release-fits
  bool intervals = false;       ///< --no-intervals
  bool features = false;        ///< --no-features
  bool write_model = false;     ///< --write-model
  bool history_weight = false;  ///< --history-weight (weigh_histories)
};

/// The help of --alpha on diagnose and report (ladder prefixes "--auto: ").
inline constexpr const char* kDiagnosisAlphaHelp =
    "Family-wise error rate of the candidate tests: alpha / 2 for the score test (step-down "
    "max-T), alpha / 2 for the held-out test (Holm); the confidence set of laws is at level "
    "alpha / 2 too";

/// What `compare`, `diagnose` and `ladder` read from their command line.
struct DiagnosisCliOptions {
  std::string data;   ///< the impact set (.csv, .h5)
  std::string where;  ///< --where: keep only the releases matching this filter; empty: all
  ModelOptions model;
  diagnosis::OptionValues values;
  OutputOptions output;
  std::string figures;      ///< directory of the SVG figures; empty: none
  std::string write_model;  ///< model file (TOML) of the best model found; empty: none
  bool shape_given = false;
  double history_weight = 0;  ///< --history-weight; 0: the rebounds alone
};

/// Adds a subcommand reading one impact set with the model, diagnosis (`set`), --figures and
/// output options; `extra` (may be empty) declares the command's own options, after the model
/// options; `run` is called with the parsed options.
CLI::App* add_diagnosis_command(CLI::App& app, const std::string& name,
                                const std::string& description, const DiagnosisOptionSet& set,
                                const std::function<void(CLI::App*)>& extra,
                                const std::function<void(DiagnosisCliOptions&)>& run);

/// Declares the diagnosis options of `set` on `sub`, writing into `values`.
void add_diagnosis_options(CLI::App* sub, diagnosis::OptionValues& values,
                           const DiagnosisOptionSet& set);

/// The command line's names of the DiagnoseOptions fields these options set, for
/// refuse_problems (cli_common.hpp).
const OptionNames& diagnosis_option_names();

/// The library's options from the values given (diagnosis::make_options), refused under the
/// command line's option names when DiagnoseOptions::problems() finds any (exit status 2,
/// before any work).
diagnosis::DiagnoseOptions diagnose_options(const diagnosis::OptionValues& values);

/// The contact histories of the releases of a set (measured_histories, aligned with in.set) and
/// their replicate floor (force_history_floor: the set's own replicates, else --floor-replicates'),
/// or no floor when fewer than two releases keep a history.
struct SetHistories {
  std::vector<std::optional<diagnosis::MeasuredHistory>> histories;
  std::optional<diagnosis::ForceHistoryScatter> floor;
};

/// Reads the histories of o.data; with --history-weight W > 0 every population fit of `opt`
/// (the full set's and each split's, on its training releases alone) then minimises Eq. 7 plus
/// W x their error in floors (diagnosis/history_objective.hpp). Call after borrow_floor. Exit 2
/// (InputError naming --history-weight) when W > 0 and fewer than two releases keep a history,
/// or the histories have no replicate floor.
SetHistories weigh_histories(diagnosis::DiagnoseOptions& opt, const DiagnosisCliOptions& o,
                             const diagnosis::Inputs& in);

/// The force histories' table: per rung (its label in `rungs`, aligned with `errors`) the RMS of
/// measured minus model in-sample / held-out +- its SE over releases, per component; with a
/// replicate floor, its row and each rung's held-out RMS over it ("x floor": issue 33's 2 x
/// reads there). Nothing when `errors` is empty.
void print_force_history(const std::vector<std::string>& rungs,
                         const std::vector<diagnosis::ForceHistoryError>& errors,
                         const std::optional<diagnosis::ForceHistoryScatter>& floor);

/// Prints "wrote FILE" for every figure and for the --out file (when given).
void print_written(const std::vector<std::string>& figures, const std::string& out);

}  // namespace ricochet::cli
