// Paired comparison of two conditions of the same impacts in one impact set (`ricochet paired`,
// docs/commands/paired.md): the resolved model's numerical checks, where each impact is run twice,
// once per condition, with everything else equal (issue 32: a stiffness plateau, E_grain 1.5e8
// against 1.5e9 Pa on the same bed seed and incident state; a convergence study: grain size, bed
// depth or width).
//
// Pairs: an impact of the base condition and one of the other whose ids are equal once each
// condition's prefix is removed ("E1.5e8-T18-s0" and "E1.5e9-T18-s0" with prefixes "E1.5e8-"
// and "E1.5e9-" pair under the key "T18-s0"). The difference of a pair, other minus base, per
// V_out component, is expressed in the scale of the impacts' shape (e.g. the lab's standard
// deviation of that component for that shape), so that pairs of different shapes pool.
//
// Per component: the mean paired difference d, its sample sd, and the Student t interval
// d +- t_{n-1, (1+level)/2} sd / sqrt(n). The rule of docs/resolved-model.md ("Stiffness plateau
// (issue 32)"): a component holds when its interval contains 0 (it moves by less than the replica
// scatter can tell) or |d| < margin (it moves by less than `margin` scales); all hold when every
// component does. With fewer than 2 pairs the interval is undefined and nothing holds.
//
// Also the comparison's output layer (JSON, CSV, text), as table2.hpp is `ricochet stats`'s.
#pragma once

#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/option_problems.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::stats {

struct PairedOptions {
  double level = 0.95;   ///< of the t interval
  double margin = 0.25;  ///< in scale units

  /// The allowed ranges (problems(); the command line shows them in --help): a level strictly
  /// between 0 and 1 (the t quantile's domain); a margin is a distance, any non-negative one
  /// (0: the interval alone decides).
  static constexpr OptionRange kLevel{0, 1, true, true};
  static constexpr OptionRange kMargin{0, INFINITY, false, true};
  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// paired_comparison calls it at its entry.
  OptionProblems problems() const;
};

/// One V_out component over the pairs (differences in scale units).
struct PairedComponent {
  std::size_t n = 0;
  double mean = 0, sd = 0, lo = 0, hi = 0;  ///< NaN with fewer than 2 pairs (sd, lo, hi)
  bool interval_holds_zero = false;
  bool within_margin = false;
  bool holds = false;  ///< interval_holds_zero || within_margin
};

struct PairedComparison {
  std::string base, other;  ///< the two id prefixes
  PairedOptions options;
  /// The scales given, per shape (V_out^x, V_out^y, omega_out; m/s, m/s, rad/s).
  std::map<std::string, std::array<double, 3>> scales;
  std::vector<std::string> keys;  ///< the pairs' keys, in the set's order of the base impacts
  std::vector<std::string> shapes;
  /// Per pair: other minus base, V_out^x, V_out^y, omega_out, in the shape's scale units.
  std::vector<std::array<double, 3>> differences;
  /// Ids with one of the prefixes whose partner is not in the set (e.g. an impact that did not
  /// rebound, or not run yet).
  std::vector<std::string> unpaired;
  std::array<PairedComponent, 3> components;
  bool all_hold = false;
};

/// A set's V_out standard deviations (V_out^x, V_out^y, omega_out; m/s, m/s, rad/s), as paper
/// Table 2 gives them (table2.hpp): the scales of a lab set's shape. Throws InputError(set.source,
/// 0, "shape", ...) for an empty set.
std::array<double, 3> vout_std(const ImpactSet& set);

/// The comparison (file comment). `scale` maps a shape name to its scales; a paired impact of a
/// shape it lacks, or a scale that is not positive, throws InputError(set.source, 0, "shape",
/// ...) naming the shape. Throws InputError for options with problems (PairedOptions::problems),
/// std::invalid_argument for equal or empty prefixes, InputError(set.source, 0, "id", ...) when
/// no pair is found.
PairedComparison paired_comparison(const ImpactSet& set, const std::string& base,
                                   const std::string& other,
                                   const std::map<std::string, std::array<double, 3>>& scale,
                                   const PairedOptions& options = {});

/// The JSON keys of docs/commands/paired.md: base, against, level, margin, scales, pairs,
/// unpaired, components, all_hold (NaN written as null).
nlohmann::json to_json(const PairedComparison& c);
/// One row per pair: key, shape, the three differences in scale units; a comment line naming
/// `data`, the impact set compared. `option` names the option in a write error.
void write_csv(const std::string& path, const PairedComparison& c, const std::string& data,
               const std::string& option = "--out");
/// The comparison as `ricochet paired` prints it (`data`: the impact set compared).
std::string format_text(const PairedComparison& c, const std::string& data);

}  // namespace ricochet::stats
