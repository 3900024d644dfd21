// Compare a model with an impact set, diagnose which effect is missing, and climb the ladder of
// models (issues 6 and 10). Every calibration is done by the fit module (fit/fit.hpp) through
// assess() (diagnosis/assess.hpp): leak-free repeated k-fold held-out errors. The files:
//   compare.cpp    compare(): the base model, its noise floor, trends, regimes, KS tests
//   ranking.cpp    diagnose(): candidates judged by held-out error, multiplicity-controlled
//   signature.cpp  the score test and the effects' declared signatures (Effect::signature())
//   confidence.cpp the confidence set of laws: multiple comparisons with the best on the score
//                  statistics (confidence.hpp)
//   power.cpp      the weakest law of each family the set would detect (power.hpp)
//   scatter.cpp    the population scatter of the calibrated parameters (scatter.hpp)
//   evidence.cpp   words with numbers: evidence, verdict summary, what is left unexplained
//   ladder.cpp     ladder(), auto_ladder()
//   diagnosis_json.cpp  the JSON documents (docs/commands/*.md)
//
// compare():  the model calibrated on the set (population and per release), the noise floor,
//             errors per observable, per release and per regime (thirds of |V_in|), residual
//             and parameter trends against impact features (Holm-controlled family), KS tests.
// diagnose(): candidates are the registered effects not in the model: the hand-written catalog,
//             plugins, and the generated coefficient laws (effects/coefficient_law.hpp). Every
//             candidate is tested, without calibration, by the robust score test of its added
//             parameters at their neutral values (signature.hpp: the change each parameter
//             makes to the predictions, projected off the base parameters' directions, against
//             the base model's residuals; the variance from the releases' own contributions),
//             and the family-wise error over ALL candidates is controlled by the step-down
//             max-T adjustment (stats/score_tests.hpp: the candidates' statistics are strongly
//             correlated, so their joint null distribution, drawn by a multiplier bootstrap,
//             replaces Holm's worst case). The `screen` candidates of largest statistic are
//             then added at their neutral values, recalibrated split by split from the base
//             model's fold optima, and their leak-free held-out error is compared with the
//             base model's by the corrected resampled t-test of the drop (Nadeau & Bengio 2003),
//             Holm over the whole family. Two routes, each at alpha / 2 (Bonferroni over the
//             two, so the family-wise level stays alpha):
//               supported  <=>  held-out error drop > 0  and
//                               (score max-T adjusted p < alpha / 2  or
//                                held-out Holm-adjusted p < alpha / 2).
//             The score test is the more powerful for effects near the detection limit (the
//             detection benchmark); the held-out test for strong effects far from linear at
//             the neutral value, whose local score can even point the wrong way (engine-made
//             sets with penetration and duration: rate_restitution T = -1.4 while its held-out
//             drop had t = 3.6).
//             When the best single term is supported but leaves the model above its floor,
//             pairs of it with the next candidates are tried (a sparse search, tested after
//             the singles: a fixed sequence, so it keeps the family-wise level; a pair is
//             supported when it beats its first effect alone by the corrected test at
//             alpha / (candidates - 1): Bonferroni over every partner the data could have
//             picked, so the partner's selection by the same data's scores is accounted for;
//             issue 31, 5e). Later `ladder --auto` rounds are a fixed sequence of nested
//             hypotheses ("the model of round r misses nothing"; docs/diagnosis.md, "Selection
//             across rounds"). Ranking: supported first, then by penalised held-out error.
//             Verdict, never contradicting the ranking (docs/diagnosis.md, "Verdict"):
//               "missing physics"  a candidate is supported (named), or, with none supported, a
//                                  residual or parameter trend survives Holm (unnamed);
//               "scatter"          above the measurement floor, nothing supported, no trend:
//                                  release-to-release scatter, with the population spread of
//                                  the parameters that explains it (scatter.hpp);
//               "adequate"         within the measurement floor, nothing supported.
// ladder():   rungs base, base + E1, base + E1 + E2, ... each recalibrated (warm start from the
//             previous rung, the new effect at its neutral value) with in-sample and held-out
//             errors per observable. auto_ladder() picks each next effect by diagnose().
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "diagnosis/assess.hpp"
#include "diagnosis/force_residual.hpp"
#include "diagnosis/scatter.hpp"
#include "diagnosis/trends.hpp"
#include "effects/registry.hpp"
#include "stats/stats.hpp"

namespace ricochet::diagnosis {

struct DiagnoseOptions {
  AssessOptions assess;
  TrendOptions trends;
  /// Family-wise error rate of the candidate tests (step-down max-T over the whole family).
  double alpha = 0.05;
  /// Candidates calibrated (held-out error) after the score test, by largest statistic; all of
  /// them when `candidates` names them. Each costs a leak-free calibration, most of a
  /// diagnosis's time (docs/diagnosis.md, "Cost"); the score test needs none.
  std::size_t screen = 1;
  /// Multiplier-bootstrap draws of the max-T adjustment (Monte Carlo error of an adjusted p
  /// near 0.05: about 0.0015 with 20,000).
  std::size_t score_draws = 20000;
  /// Try pairs of the best candidates when no single one brings the model within its floor.
  bool pairs = true;
  /// Pairs of the best supported candidate with the next (pair_pool - 1) candidates by score
  /// statistic whose unadjusted score p is below alpha.
  std::size_t pair_pool = 3;
  /// Effects to try; empty = every effect of the registry not in the model.
  std::vector<std::string> candidates;
  /// Registry of effects (built-ins and loaded plugins); nullptr = EffectRegistry::global().
  const EffectRegistry* registry = nullptr;
  /// Probe step of the signature test, as a fraction of the parameter's range from its neutral
  /// value towards the other bound.
  double probe_fraction = 0.1;
  /// The verdict `adequate` needs the power to back it (issue 31, 5b): every family's weakest
  /// detectable law (Diagnosis::detectable) must have z_80 <= adequate_z, i.e. a law of any
  /// family whose change of the predictions has noncentrality adequate_z would be detected with
  /// 80 % power. Otherwise a set within its floor gets `inconclusive`. 5 is the issue's own
  /// yardstick ("an effect with oracle z >= 5 must not be called adequate"); it is not tuned.
  double adequate_z = 5.0;
  bool progress = true;  ///< progress bar on a terminal

  /// The allowed ranges (problems(); the command line shows them in --help): alpha is a
  /// probability, the level of a test (0 and 1 would test nothing); screen at most 1000, far
  /// above the registry's candidates (each costs a leak-free calibration); the probe step a
  /// fraction of the range.
  static constexpr OptionRange kAlpha{0, 1, true, true};
  static constexpr OptionRange kScreen{0, 1000};
  static constexpr OptionRange kScoreDraws{1, 1e9};
  static constexpr OptionRange kProbeFraction{0, 1, true, false};
  static constexpr OptionRange kAdequateZ{0, 1e3, true, false};

  /// The problems of these options (common/option_problems.hpp; assess's prefixed "assess."),
  /// empty when they are valid; compare, diagnose, ladder and auto_ladder call it at their entry.
  OptionProblems problems() const;
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
  PopulationScatter scatter;  ///< the parameters' release-to-release spread (scatter.hpp)
  /// Two-sample KS test of the measured against the held-out predicted values, per observable.
  std::array<stats::KsResult, kObservables> ks{};
  /// Floors of the error denominators actually used (m/s, m/s, rad/s, m, s; AssessOptions::scale);
  /// for penetration and contact duration the one constant denominator of the set
  /// (fit::ErrorOptions::penetration_scale_m, contact_duration_scale_s).
  Obs error_floors{};
  double seconds = 0;
  std::uint64_t collisions = 0;  ///< simulated (engine's collisions_simulated())
};

/// `options` with their assess options resolved on `set` (resolve_scale): the first step of
/// compare, diagnose and ladder, so that everything they compute on the full set shares one set
/// of error denominators.
DiagnoseOptions resolve_scale(const ImpactSet& set, const DiagnoseOptions& options);

/// `warm`: an assessment of the same model on the same set and options whose fold fits are
/// leak-free (a ladder's previous round: its best candidate's); each fold then refines that
/// split's optimum (assess()), never a start fitted on its own held-out releases.
Baseline compare(const Model& model, const Shape& shape, const ImpactSet& set,
                 const DiagnoseOptions& options, const Assessment* warm = nullptr);

/// One candidate effect, judged.
struct Candidate {
  std::string effect;                         ///< registry name; "a+b" for a pair
  std::vector<std::string> effects;           ///< the effects added (one, or two for a pair)
  bool generated = false;                     ///< a generated coefficient law (or a pair with one)
  std::string law;                            ///< the added physics as a law with numbers and units
  std::string meaning;                        ///< what the effect stands for, in words
  std::vector<std::string> added_parameters;  ///< its calibrated parameters
  std::vector<double> added_values;           ///< their population-fit values
  Assessment assessment;                      ///< base + effect, recalibrated
  Adequacy adequacy;                          ///< of base + effect against the noise floor
  double heldout_error = 0, heldout_se = 0;
  double error_drop = 0;  ///< base - candidate held-out error (mean over releases)
  /// Standard error of the drop: error_drop / t (the test itself is on the splits' log error
  /// ratios, ranking.cpp).
  double drop_se = 0;
  double t = 0;                 ///< robust score statistic (stats/score_tests.hpp)
  double p_value = 1;           ///< unadjusted p of the score test
  double p_adjusted = 1;        ///< score test, step-down max-T adjusted over the family
  double p_holm = 1;            ///< held-out test (heldout_p), Holm-adjusted over the family
  std::size_t family_size = 0;  ///< hypotheses in the family
  double heldout_t = 0;         ///< corrected resampled t of the held-out drop (reported)
  double heldout_p = 1;         ///< its one-sided p
  /// A pair: its held-out error is also significantly below its first effect's alone
  /// (corrected resampled t-test at alpha / (candidates - 1)); a pair is supported only then.
  bool beats_first = false;
  bool contact_bias = false;     ///< the effect's signature includes a contact-feature bias
  double penalty = 0;            ///< p_added * floor / n_train
  double penalised_heldout = 0;  ///< ranking key
  bool supported = false;
  double signature_r = NAN;  ///< score-test correlation (see file comment)
  /// Declared signature trends of the effect found significant in the base model (as text).
  std::vector<std::string> signature_trends;
  std::string evidence;  ///< words with numbers
  std::string error;     ///< non-empty when the effect could not be tried
};

/// A candidate tested by the score test but not calibrated (below the `screen` best).
struct Screened {
  std::string effect;
  double signature_r = NAN;
  double t = NAN, p_value = 1, p_adjusted = 1;
};

/// One law of the confidence set (confidence.cpp): a candidate that the data cannot tell apart
/// from the best, or the law as it stands ("none").
struct LawMember {
  std::string effect;                ///< registry name, "a+b" for a pair, "none"
  std::vector<std::string> effects;  ///< the effects added (empty for "none")
  std::string law;                   ///< with numbers and units
  Family family = Family::kNone;     ///< of the first effect (Effect::kind())
  Variable variable = Variable::kNone;
  std::vector<Family> families;  ///< of every effect added ({kNone} for "none")
  /// Its score statistic T (0 for "none"; NaN for a pair, which is tested against its first
  /// effect instead), how far it is below the best law's, and the MCB critical value that gap
  /// must not exceed (confidence.hpp).
  double statistic = NAN, gap_to_best = NAN, critical = NAN;
  /// Root mean square over releases of its predictions minus the best member's, per observable
  /// (m/s, m/s, rad/s, m, s; NaN for an observable the set does not use).
  Obs differs_from_best{};
};

/// The second stage of the confidence set (encompassing.hpp): each family's best law of the
/// first stage, calibrated on the set, tested against every other family's by the non-nested
/// J test; a family whose law another one encompasses leaves the set.
struct FamilyEncompassing {
  double alpha = NAN;  ///< this stage's level (half the set's)
  /// One-sided normal quantile at 1 - alpha / (ordered pairs of laws of different families).
  double critical = NAN;
  std::vector<std::string> laws;        ///< each family's best first-stage members (their effects)
  std::vector<Family> families;         ///< of each law
  std::vector<std::string> calibrated;  ///< each law with its calibrated numbers and units
  /// t[a][b]: law a taken as true, tested in the direction of law b (NaN on the diagonal and
  /// where a law could not be calibrated).
  std::vector<std::vector<double>> t;
  /// Per law: the index of the law that encompasses it (t[a][b] > critical >= t[b][a]; the
  /// largest such t[a][b]), or -1 when it stays.
  std::vector<int> excluded_by;
  double seconds = 0;  ///< calibrations and predictions
};

/// The confidence set of laws: the laws that these data cannot tell apart from the best one at
/// level alpha. Two stages, each at alpha / 2 (so that the set holds the best law with
/// probability at least 1 - alpha): multiple comparisons with the best on the score statistics
/// (confidence.hpp), then the encompassing tests between the families' calibrated laws.
struct LawConfidenceSet {
  double alpha = 0.05;
  std::size_t models = 0;          ///< laws judged: every candidate with a statistic, and "none"
  std::vector<LawMember> members;  ///< best (largest statistic) first
  /// The second stage, run when the first rejected the law as it stands ("none") and left two
  /// candidate families or more.
  std::optional<FamilyEncompassing> encompassing;
  /// The distinct families of the members, "none" included when the law as it stands is in.
  std::vector<Family> families() const;
  bool holds_none() const;
};

/// The weakest law of one family that this set would detect with 80 % power (issue 31, item 2;
/// power.hpp): what an `adequate` or `scatter` verdict cannot rule out.
struct Detectable {
  Family family = Family::kOther;
  std::string effect;  ///< the family's most detectable candidate
  Variable variable = Variable::kOther;
  std::string parameter, unit;  ///< its parameter and the parameter's SI unit
  double neutral = NAN;         ///< where the law does nothing
  /// The change from neutral at 80 % power (signed: the side the law may take), solved on the
  /// engine within the bounds; beyond them the first-order change (infinite when t_ceiling is
  /// too low for any strength).
  double change_80 = NAN;
  /// The score statistic's mean per unit change at small changes, and its ceiling (power.hpp):
  /// to first order, at a change beta of the allowed sign, E[T] = |beta| t_per_unit / sqrt(1 +
  /// (|beta| t_per_unit / t_ceiling)^2), and the power is Phi(E[T] - critical).
  double t_per_unit = NAN, t_ceiling = NAN;
  /// E[T] at finite changes from neutral, from the engine's predictions (power.hpp, "At a
  /// finite strength"): (signed change in `unit`, E[T]) by increasing |change|, the points the
  /// search for change_80 evaluated. The power at a change is Phi(E[T] - critical).
  std::vector<std::pair<double, double>> t_curve;
  /// The parameter's value at 80 % power; NaN when that lies beyond its bounds (not detectable
  /// within them).
  double value = NAN;
  std::string law;  ///< the law at that strength, with numbers and units
  /// RMS over the set's releases of the change the law makes to the predictions at that
  /// strength, per observable (m/s, m/s, rad/s, m, s; NaN where unused).
  Obs shift{};
  double noise_units = NAN;  ///< the same change, whitened: RMS per release in noise sd
  /// The same change as a noncentrality: the norm over the whole set of the whitened change,
  /// projected off the base parameters (noise_units x sqrt(releases)). The diagnosis's analogue
  /// of the independent oracle's z (docs/detection-benchmark.md), with the set's pooled
  /// whitening where the oracle has each release's true covariance. NaN beyond the bounds.
  double z_80 = NAN;
  double power = 0.8;
  double level = NAN;     ///< the family-wise level of the test (alpha / 2, the score route)
  double critical = NAN;  ///< the max-T critical value the diagnosis uses at that level
};

struct Diagnosis {
  Baseline baseline;
  /// "missing physics" | "scatter" | "adequate" (within the floor, and every family visible at
  /// z_80 <= DiagnoseOptions::adequate_z) | "inconclusive" (within the floor, but some family
  /// is not: these data could hide a law of it; `underpowered` says which)
  std::string verdict;
  std::vector<Candidate> ranking;      ///< best first (candidates that were calibrated)
  std::vector<Screened> screened_out;  ///< candidates tested but not calibrated
  /// The laws these data cannot tell apart from the best one (issue 31, item 1).
  LawConfidenceSet confidence_set;
  /// Per family, the weakest law the set would detect (80 % power at the diagnosis's own
  /// family-wise critical value); printed with every `adequate` and `scatter` verdict.
  std::vector<Detectable> detectable;
  /// The families of `detectable` whose weakest detectable law has z_80 above
  /// DiagnoseOptions::adequate_z or none within its bounds; they make a verdict within the
  /// floor `inconclusive` instead of `adequate`.
  std::vector<Family> underpowered;
  double adequate_z = NAN;  ///< DiagnoseOptions::adequate_z of this diagnosis
  /// The same for every tested candidate parameter (JSON `minimum_detectable_by_candidate`):
  /// the power of the test of a named law at any strength (power calibration,
  /// docs/detection-benchmark.md).
  std::vector<Detectable> detectable_candidates;
  std::size_t family_size = 0;  ///< hypotheses in the max-T family (every candidate)
  /// With no supported candidate: the Holm-significant trends (unnamed missing physics).
  std::vector<std::string> unnamed_structure;
  std::string summary;                   ///< one or two sentences
  std::vector<std::string> unexplained;  ///< residual structure left after the best candidate
  double seconds = 0;
  /// Collisions simulated by the diagnosis and its baseline (engine's collisions_simulated()).
  std::uint64_t collisions = 0;
  /// The same by phase, in order: baseline, score, rank, pairs, confidence, power.
  std::vector<std::pair<std::string, std::uint64_t>> collisions_by_phase;
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
  std::string law;    ///< the added effect as a law with numbers (Effect::law)
  /// The force-law rung only: its held-out errors use the law discovered again on each split's
  /// training histories; how many splits did so, and how many found the same terms as the
  /// full set.
  std::size_t split_discoveries = 0, split_same_terms = 0;
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
/// Adds a rung "force law" to `l` (issue 33, item 3): the force law discovered on the contact
/// histories `data` keeps (force_law_from_tracks, each release at its own calibration of the last
/// rung's model, fit::calibrate_releases) as `term_<name>` effects at their discovered
/// coefficients, held fixed (the histories identify them; the rebounds do not), the rest of the
/// model recalibrated and judged like any rung. Its held-out errors are leak-free: each split
/// discovers the law again on its training releases' histories alone and calibrates that model
/// (assess with a SplitModel). Returns the full-set discovery (nullopt when `data` keeps fewer
/// than two histories); no rung is added when it selects no term. `base` is the model the
/// ladder started from (rung_model). `named`: a named law instead (named_force_terms): these
/// terms' coefficients fitted on the histories, without selection, on the full set and again on
/// each split's training histories.
std::optional<ForceLawReport> add_force_law_rung(Ladder& l, const Model& base, const Shape& shape,
                                                 const ImpactSet& set, const std::string& data,
                                                 const DiagnoseOptions& options,
                                                 std::span<const ForceTerm* const> named = {});
/// Rounds of diagnose(): adds the best supported effect until the model is adequate, no effect
/// is supported, or `max_rounds` effects were added.
/// `first`: an existing diagnosis of `model` on `set` (same options) used as round 0.
Ladder auto_ladder(const Model& model, const Shape& shape, const ImpactSet& set, int max_rounds,
                   const DiagnoseOptions& options, const Diagnosis* first = nullptr);

/// The model of a rung, with its calibrated values (to continue from it).
Model with_values(const Model& model, const std::vector<double>& values);
/// Rung `rung` of a ladder (0 = the base) as a model with its calibrated values: `base` plus the
/// effects the rungs up to it added, in the ladder's parameter order (its fold_params' too).
Model rung_model(const Model& base, const Ladder& l, std::size_t rung,
                 const EffectRegistry& registry = EffectRegistry::global());
/// The last rung of a ladder as a model with its calibrated values (`ladder --write-model`).
Model ladder_model(const Model& base, const Ladder& l,
                   const EffectRegistry& registry = EffectRegistry::global());
/// The base model plus the best supported candidate of `d` with its calibrated values (the
/// model file `diagnose --write-model` writes); the base model when nothing is supported.
Model best_model(const Model& base, const Diagnosis& d,
                 const EffectRegistry& registry = EffectRegistry::global());

nlohmann::json to_json(const Assessment& a, const NoiseFloor& floor);
nlohmann::json to_json(const Baseline& b, const ImpactSet& set);
nlohmann::json to_json(const Candidate& c, const std::array<bool, kObservables>& use);
/// The confidence set of laws as JSON: its members (`effect`, `law`, `family`, `families`,
/// `variable`, `statistic`, `differs_from_best`) and how it was made.
nlohmann::json to_json(const LawConfidenceSet& cs, const std::array<bool, kObservables>& use);
/// The `ricochet diagnose --json` document (docs/commands/diagnose.md).
nlohmann::json to_json(const Diagnosis& d);
/// The `ricochet ladder --json` document (docs/commands/ladder.md).
nlohmann::json to_json(const Ladder& l);

/// Writes a result to `path` by its extension: .csv, a table (one row per release for a
/// Baseline, per candidate for a Diagnosis, per rung for a Ladder); .h5/.hdf5, the arrays under
/// /compare, /diagnosis or /ladder with `doc` (the --json document) as attribute "json" (a
/// Baseline's file is also an impact set: `set` goes to /impacts). Layouts:
/// docs/commands/{compare,diagnose,ladder}.md. The caller checks the extension.
void write_file(const std::string& path, const Baseline& b, const ImpactSet& set,
                const nlohmann::json& doc);
void write_file(const std::string& path, const Diagnosis& d, const nlohmann::json& doc);
void write_file(const std::string& path, const Ladder& l, const nlohmann::json& doc);

}  // namespace ricochet::diagnosis
