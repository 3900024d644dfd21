// Inputs shared by the compare, diagnose, ladder and report commands: the data set restricted to
// one shape, the model, and the options, with errors that name the option or file at fault.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"
#include "diagnosis/force_history.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::diagnosis {

/// Option values as given on a command line. Every default is the library's, read from
/// DiagnoseOptions / AssessOptions (the one place each is decided, with its reason), so that the
/// command line and a program calling the library run the same analysis.
struct OptionValues {
  /// Number of folds, or "loro" (leave one release out): the text parse_folds reads.
  std::string folds = std::to_string(AssessOptions{}.folds);
  /// Seed of every random draw of the analysis: the calibrations' start designs, the
  /// cross-validation's partitions (CvDesign) and the score test's multiplier bootstrap.
  std::uint64_t seed = AssessOptions{}.fit.seed;
  double alpha = DiagnoseOptions{}.alpha;            ///< family-wise error rate
  std::size_t repeats = AssessOptions{}.repeats;     ///< repeated k-fold partitions
  std::size_t screen = DiagnoseOptions{}.screen;     ///< generated laws calibrated
  double adequate_z = DiagnoseOptions{}.adequate_z;  ///< power gate of `adequate`
  bool no_pairs = !DiagnoseOptions{}.pairs;          ///< skip the pair search
  std::vector<std::string> candidates;
  bool no_release_fits = !AssessOptions{}.release_fits;    ///< skip per-release calibration
  bool no_intervals = !AssessOptions{}.release_intervals;  ///< per-release fits without intervals
  bool no_features = !AssessOptions{}.use_features;  ///< ignore penetration / contact duration
  /// An impact set whose replicate scatter is the floor of a set without replicates
  /// (AssessOptions::borrowed_floor); empty: none.
  std::string floor_replicates;
  /// Keeps only the releases of floor_replicates matching this filter (the --where syntax, e.g.
  /// "id^=E1.5e9-": one level of a campaign); empty: all of the shape.
  std::string floor_where;
  /// Error denominators: set-mean or eq7 (ErrorScale).
  std::string error = error_scale_name(AssessOptions{}.scale);
  /// Marginal orientation grid of non-disc blocks without alpha_in (0 also means this default).
  int orientations = AssessOptions{}.fit.alpha.marginal_points;
  /// The refined orientation rule (polish and predictions; 0: none).
  int polish_orientations = AssessOptions{}.fit.alpha.polish_points;
  /// BOBYQA runs of cold fits on sets of unknown orientation (AssessOptions::marginal_starts).
  int orientation_starts = AssessOptions{}.marginal_starts;
  /// BOBYQA step tolerance of the searches whose ends are polished
  /// (fit::AlphaOptions::search_xtol).
  double search_xtol = AssessOptions{}.fit.alpha.search_xtol;
  /// The global search of cold fits on sets of unknown orientation (fit::OrientationSearch).
  std::string orientation_search = fit::orientation_search_name(AssessOptions{}.fit.alpha.search);
  int threads = AssessOptions{}.fit.threads;      ///< OpenMP threads, 0 = all
  double dt_s = AssessOptions{}.fit.engine.dt_s;  ///< engine time step [s]
};

/// Builds DiagnoseOptions from the values; throws InputError naming the option for a value
/// that does not parse (--folds, --error). The ranges (the time step's too) are
/// DiagnoseOptions::problems()'s: the caller checks them (the command line under its own option
/// names).
DiagnoseOptions make_options(const OptionValues& values);

/// An impact set restricted to one shape, and that shape.
struct Inputs {
  ImpactSet set;
  Shape shape;
};

/// The shapes an analysis of `set` covers: {shape_name} when the user named one (--shape), else
/// every shape present in the data, in order of first appearance. The one rule for choosing the
/// shape: load_inputs takes the only one, `report` each in turn.
std::vector<std::string> shapes_to_analyse(const ImpactSet& set, const std::string& shape_name);

/// The releases of `set` (read from `data`) of shape `shape_name` (Shape::resolve; a bad name is an
/// InputError naming --shape). Fewer than 4 is an InputError naming `data`: the held-out error
/// needs at least 4.
Inputs select_inputs(const ImpactSet& set, const std::string& shape_name, const std::string& data);

/// Reads DATA, keeps the releases matching `where` (impact filter, the --where syntax; empty: all;
/// none kept is an InputError) and of one shape (select_inputs): `shape_name`, or when it is empty
/// the only one present in the data (an error lists them when there are several).
Inputs load_inputs(const std::string& data, const std::string& shape_name,
                   const std::string& where = "");

/// The replicate scatter (replicate_scatter) of the impact set at `path`, its releases of shape
/// `shape` matching `where` (the --where syntax; "" = all) only, with `source` = path and `where`:
/// the floor a set without replicates borrows. An InputError (file, field `option`) when it has
/// fewer than two replicate groups; a filter that keeps nothing is one naming `where_option`.
ReplicateScatter borrowed_scatter(const std::string& path, const std::string& shape,
                                  const std::string& option, const std::string& where = "",
                                  const std::string& where_option = "--floor-where");

/// Sets options.assess.borrowed_floor from values.floor_replicates and values.floor_where
/// (borrowed_scatter of the inputs' shape, errors naming --floor-replicates or --floor-where);
/// nothing when the file is empty.
void borrow_floor(DiagnoseOptions& options, const OptionValues& values, const Inputs& inputs);

/// The replicate floor of the force histories (force_history_scatter) that `ladder` and `report`
/// read their error against: `set`'s own replicate groups when one has two histories or more
/// (`histories` aligned with set.impacts, measured_histories), else those of the releases whose
/// V_out scatter the set borrows (`borrowed`, borrowed_scatter's: its source file's releases of
/// `shape` matching its filter, already checked there; source and where copied), else nullopt.
/// A borrowed file without replicate histories gives nullopt: the V_out floor does not need them.
std::optional<ForceHistoryScatter> force_history_floor(
    const ImpactSet& set, const Shape& shape,
    const std::vector<std::optional<MeasuredHistory>>& histories,
    const std::optional<ReplicateScatter>& borrowed);

}  // namespace ricochet::diagnosis
