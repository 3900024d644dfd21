// The validation report of `ricochet report`: for each impact set (lab shapes, a LIGGGHTS
// campaign, synthetic data) the data, the comparison of the model with it, the diagnosis, the
// model ladder chosen by rounds of diagnosis, and conclusions, in one self-contained HTML page
// (report/html.hpp) with every figure embedded.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"
#include "diagnosis/force_history.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"
#include "stats/lab_gap.hpp"

namespace ricochet::diagnosis {

/// One analysed set: its file, the releases of one shape, and a label (e.g. "lab cylinders").
struct ReportInput {
  std::string data;
  std::string label;
  ImpactSet set;
  Shape shape;
  /// A measured set of the same shape to compare this one with (`report --against`): a resolved
  /// campaign against the lab. Not owned; empty lab_data = none.
  const ImpactSet* lab = nullptr;
  std::string lab_data;
  /// `lab` holds only the releases this set was run at (every impact's id names one of lab_data's
  /// releases, impact/release_index.hpp), not the whole file.
  bool lab_matched = false;
  /// Another set's replicate scatter on the same ground, the floor of this set when it has no
  /// replicates of its own (`report --data-floor-replicates`; AssessOptions::borrowed_floor
  /// of this set's diagnosis and ladder). Absent: the set's own sources.
  std::optional<ReplicateScatter> borrowed_floor;
};

struct ReportOptions {
  DiagnoseOptions diagnose;
  int rounds = 2;  ///< at most this many effects added by the automatic ladder
  std::string title = "Ricochet validation report";

  /// The allowed range of rounds (problems(); the command line shows it in --help).
  static constexpr OptionRange kRounds{0, 20};
  /// The problems of these options (diagnose's prefixed "diagnose."), empty when they are
  /// valid; analyse() calls it at its entry.
  OptionProblems problems() const;
};

/// Results of one analysed set (also returned as JSON by `ricochet report --json`).
struct ReportSection {
  ReportInput input;
  Diagnosis diagnosis;  ///< round 0 (contains the comparison)
  Ladder ladder;        ///< automatic ladder (rung 0 = the base model)
  /// One sentence: what fails (and on which observable), what the diagnosis found, how far the
  /// ladder brought the error. The section and the page's conclusions open with it.
  std::string headline;
  std::string conclusion;  ///< the long form, with every number
  /// The set against ReportInput::lab (stats/lab_gap.hpp), and its one-sentence summary.
  std::optional<stats::LabGap> lab_gap;
  std::string lab_sentence;
  /// A set whose file keeps contact histories: the force law the base model leaves, each
  /// release at its own calibration (force_law_from_tracks); nullopt otherwise.
  std::optional<ForceLawReport> force_law;
  /// The contact histories of the set's releases (measured_histories, aligned with input.set;
  /// all nullopt for a file that keeps none), read once for everything above and below.
  std::vector<std::optional<MeasuredHistory>> histories;
  std::string force_law_error;  ///< why the histories could not be read (the page says it)
  /// Each ladder rung's force-history error (ladder_force_history; empty without histories) and
  /// their replicate floor (force_history_floor: the set's own replicates, else the file of
  /// borrowed_floor; nullopt without replicate histories).
  std::vector<ForceHistoryError> force_history;
  std::optional<ForceHistoryScatter> force_floor;
};

/// Runs compare, diagnose and the automatic ladder on every input.
std::vector<ReportSection> analyse(const std::vector<ReportInput>& inputs, const Model& model,
                                   const ReportOptions& options);

/// Writes the HTML page to `path`; returns the number of embedded figures.
std::size_t write_report(const std::vector<ReportSection>& sections, const Model& model,
                         const ReportOptions& options, const std::string& path);

/// Short JSON summary per section (verdict, floor, errors per rung, best effect, conclusion).
nlohmann::json to_json(const std::vector<ReportSection>& sections);

}  // namespace ricochet::diagnosis
