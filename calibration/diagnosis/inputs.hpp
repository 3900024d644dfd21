// Inputs shared by the compare, diagnose, ladder and report commands: the data set restricted to
// one shape, the model, and the options, with errors that name the option or file at fault.
#pragma once

#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::diagnosis {

/// Option values as given on a command line.
struct OptionValues {
  std::string folds = "5";  ///< number of folds, or "loro" (leave one release out)
  std::uint64_t seed = 1;   ///< seed of the calibration's start designs
  // Defaults are the library's (one place: DiagnoseOptions / AssessOptions).
  double alpha = DiagnoseOptions{}.alpha;         ///< family-wise error rate
  std::size_t repeats = AssessOptions{}.repeats;  ///< repeated k-fold partitions
  std::size_t screen = DiagnoseOptions{}.screen;  ///< generated laws calibrated
  bool no_pairs = false;                          ///< skip the pair search
  std::vector<std::string> candidates;
  bool no_release_fits = false;    ///< skip per-release calibration (faster)
  bool no_intervals = false;       ///< per-release fits without identifiability intervals
  bool no_features = false;        ///< ignore penetration / contact duration
  std::string error = "set-mean";  ///< error denominators: set-mean or eq7 (ErrorScale)
  int orientations = 0;  ///< marginal orientation grid of non-disc blocks (0 = fit default)
  int threads = 0;
  double dt_s = 1e-5;
};

/// Builds DiagnoseOptions; throws InputError naming the option for a bad value.
DiagnoseOptions make_options(const OptionValues& values);

/// Resolves the number of folds for a set of n releases ("loro" = n; clamped to [2, n]).
std::size_t resolve_folds(const std::string& folds, std::size_t n);

/// Reads DATA, keeps the releases matching `where` (impact filter, the --where syntax; empty: all;
/// none kept is an InputError) and of `shape` (fit::select_shape). When `shape_name` is empty
/// the shape is the only one present in the data (an error lists them when there are several).
struct Inputs {
  ImpactSet set;
  Shape shape;
};
Inputs load_inputs(const std::string& data, const std::string& shape_name,
                   const std::string& where = "");

}  // namespace ricochet::diagnosis
