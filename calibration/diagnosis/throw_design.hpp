// The throws that would decide between rival laws (issue 31, item 3; `ricochet design`,
// docs/commands/design.md).
//
// Given an impact set SET, a base model and rival laws (rivals.hpp: the base model alone or
// with added effects), each calibrated on SET:
//  1. the noise: the pooled covariance of the base model's scaled in-sample residual vectors on
//     SET, the covariance the score test whitens with (signature.hpp, base_directions: W =
//     L^-1, S = L L^T over the observables the set carries);
//  2. the candidates: K incident states of a low-discrepancy (Sobol') sequence in the box
//     (OpenTURNS SobolSequence; Sobol' 1967, USSR Comput. Math. Math. Phys. 7:86), every one of
//     them predicted by every rival and by its parameter probes in one engine batch per
//     parameter vector (fit::predict: blocks without alpha_in averaged over the orientation
//     grid, AssessOptions::fit.alpha, as every orientation-sampled set is);
//  3. the per-state terms of the T-criterion for every ordered pair (discrimination.hpp), with
//     each state's error denominators D_s those of the set's rule (AssessOptions::scale) at the
//     base model's prediction for a new state (it has no measurement yet), the measured V_out
//     for a state of the set;
//  4. the design: SET's states plus `budget` candidates, max-min over the pairs of rivals by
//     greedy selection and exchange (select_max_min), and for comparison `budget` states drawn
//     uniformly in the box (seeded) and SET alone.
// A candidate at which a rival, or one of its parameter probes, predicts no rebound (the block
// stays in the sand, CollisionStatus) is never chosen, and carries no information in the
// uniform draw. Pairs whose calibrated rivals predict the same everywhere (lambda below
// DesignOptions::indistinguishable_lambda even with every candidate thrown: typically an effect
// calibrated at its neutral value, which IS the base model) cannot be decided by any throw:
// they are reported and left out of the max-min. So are pairs beyond the budget: those whose own
// best plan (the greedy selection for that pair alone) would still give a power below
// DesignOptions::budget_power. The max-min is a minimum: one pair no plan of this size could
// decide (seen in the closed loop: a rival calibrated at 1e-3 of its effect's range from neutral
// against the base model, lambda 0.003 with the best 40 throws) would otherwise set it, and the
// plan would spread the throws by the needs of a pair it cannot help instead of deciding the
// others (docs/detection-benchmark.md, the closed loop).
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "diagnosis/rivals.hpp"
#include "diagnosis/synth.hpp"

namespace ricochet::diagnosis {

/// The box spanned by a set's incident states (min to max of each component).
/// (The box of candidate states is synth's WideBox: V_in^x, V_in^y, omega_in ranges, SI.)
WideBox box_of(const ImpactSet& set);

struct DesignOptions {
  /// Calibration of the rivals, error denominators, orientation grid, engine, threads, seed of
  /// the calibrations' start designs (fit.seed).
  AssessOptions assess;
  std::size_t budget = 40;  ///< new throws
  /// Candidate states (Sobol' points); 0 = max(1024, 4 x budget).
  std::size_t candidates = 0;
  /// Family-wise level behind the predicted power: with m rivals other than the base model alone,
  /// each pair is tested at alpha / (r^2 m (m - 1)) (ThrowDesign::test_level).
  double alpha = 0.05;
  std::uint64_t seed = 1;        ///< of the uniform draw the plan is compared with
  std::size_t max_passes = 100;  ///< exchange passes at most (each swaps a state at most once)
  /// Pairs whose lambda with every candidate thrown stays below this are indistinguishable.
  double indistinguishable_lambda = 1e-3;
  /// Pairs whose own best plan of `budget` throws stays below this power are beyond the budget.
  double budget_power = 0.5;
  const EffectRegistry* registry = nullptr;  ///< nullptr = EffectRegistry::global()

  /// The allowed ranges (problems(); the command line shows them in --help). budget: one throw
  /// at least, 1e4 bounds the selection's exchange passes over the plan; candidates: 0 (the
  /// default size) or at least the budget, 1e6 bounds the predictions held in memory; alpha: a
  /// family-wise error rate, at most 0.5 (beyond, the tests err more often than not), at least
  /// 1e-6 (each pair's level divides it again by r^2 m (m - 1)); a power lies in [0, 1].
  static constexpr OptionRange kBudget{1, 1e4};
  static constexpr OptionRange kCandidates{0, 1e6};
  static constexpr OptionRange kAlpha{1e-6, 0.5};
  static constexpr OptionRange kPasses{0, 1e4};
  static constexpr OptionRange kIndistinguishable{0, INFINITY, false, true};
  static constexpr OptionRange kPower{0, 1};
  /// The problems of these options (common/option_problems.hpp), empty when they are valid;
  /// assess's prefixed "assess.". design_throws calls it at its entry.
  OptionProblems problems() const;
};

/// One pair of rivals on one design.
struct PairOnDesign {
  double lambda_ab = 0;  ///< rival a true, b refitted
  double lambda_ba = 0;  ///< rival b true, a refitted
  double lambda = 0;     ///< the pair's value (min of the two; nested: the larger law true)
  double power = 0;      ///< at ThrowDesign::test_level
};

struct PairResult {
  std::size_t a = 0, b = 0;  ///< indices into ThrowDesign::rivals
  bool nested = false;       ///< one rival's effects are a subset of the other's
  bool indistinguishable = false;
  bool beyond_budget = false;       ///< even its own best plan stays below budget_power
  PairOnDesign plan, uniform, set;  ///< SET + plan, SET + the uniform draw, SET alone
  PairOnDesign alone;               ///< SET + the greedy plan for this pair alone
};

struct ThrowDesign {
  std::string shape;
  WideBox box;
  std::size_t releases = 0;    ///< of SET
  std::size_t candidates = 0;  ///< K
  std::size_t excluded = 0;    ///< candidates where a rival predicts no rebound
  std::vector<Rival> rivals;
  std::array<bool, kObservables> use{};  ///< observables of SET (whitened together)
  std::vector<Vel3> plan;                ///< the chosen incident states, in selection order
  std::vector<Vel3> uniform;             ///< the uniform draw of the same size
  std::vector<PairResult> pairs;
  /// The criterion (min over the decidable pairs) and the smallest power, per design.
  PairOnDesign min_plan, min_uniform, min_set;
  double greedy_lambda = 0;  ///< the plan's criterion after the greedy stage, before exchanges
  std::size_t passes = 0, swaps = 0;
  double alpha = 0.05;
  /// The level of each pair's test behind `power`: alpha / (r^2 m (m - 1)) for m >= 2 rivals
  /// other than the base model alone and r = kFamilyRepresentatives, as a two-sided chi^2_1
  /// level, i.e. the one-sided normal critical value z(1 - (alpha / 2) / (r^2 m (m - 1))) of the
  /// diagnosis's second stage (encompassing.hpp: alpha / 2 over the ordered pairs of laws of
  /// different families, r laws per family at most); alpha itself for m < 2.
  double test_level = 0.05;
  std::uint64_t seed = 1;
  /// Wall times [s]: calibration of the rivals, predictions, selection, total.
  double calibration_s = 0, prediction_s = 0, selection_s = 0, seconds = 0;
};

/// The design (file comment). `rivals`: the effects of each rival (parse_rivals). Options with
/// problems (DesignOptions::problems) and a box with problems (WideBox::problems) are refused
/// with InputError before any calibration.
ThrowDesign design_throws(const Model& base, const Shape& shape, const ImpactSet& set,
                          const std::vector<std::vector<std::string>>& rivals, const WideBox& box,
                          const DesignOptions& options);

/// The `ricochet design --json` document's result part (docs/commands/design.md).
nlohmann::json to_json(const ThrowDesign& d);

/// Writes the plan as an impact set of incident states (CSV, docs/impact-sets.md "Incident
/// states"): columns id, shape, vin_x[m/s], vin_y[m/s], win[rad/s], ids D001, D002, ...;
/// `comments` first, as '#' lines. Through CsvTable (common/csv.hpp); `option` names the
/// option in a write error.
void write_plan_csv(const ThrowDesign& d, const std::string& path,
                    const std::vector<std::string>& comments, const std::string& option = "--out");

}  // namespace ricochet::diagnosis
