// The force-history error of a calibrated model (issue 33, item 3): how far the contact force a
// model gives along each release's own measured path lies from the measured one, in-sample and
// on held-out releases, so that `ladder` shows the force histories' error falling rung by rung
// beside the rebound error. And the discovered law as a model: the base model plus the
// force-residual discovery's terms (effects/force_term.hpp) at their discovered coefficients
// (`diagnose --write-force-model`).
//
// Held out means what it means for the rebound error (assess.hpp): the model of a split is
// calibrated on that split's training releases (Assessment::fold_params, from data-free starts)
// and its force is compared along the test releases' histories only. The histories themselves
// never enter a calibration (the fits read V_out). The `--force-law` rung discovers its law
// again on each split's training histories (Assessment::fold_models), so that its held-out
// errors, rebounds and forces, never see the held-out releases' histories either.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "diagnosis/assess.hpp"
#include "diagnosis/diagnose.hpp"
#include "diagnosis/figures.hpp"
#include "diagnosis/force_residual.hpp"

namespace ricochet::diagnosis {

/// RMS over the contact samples (force_residual's: the law's deepest slot in contact) of the
/// residual normal force, tangential force [N] and moment [N m]; NaN for a component that no
/// history measures (a track without torque has no moment).
struct ForceHistoryError {
  std::array<double, kForceComponents> insample_rms{};  ///< at the full-set calibration
  std::array<double, kForceComponents> heldout_rms{};   ///< each release at its splits' fits
  /// Standard error of heldout_rms over the releases (pooled_rms_se of their held-out sums of
  /// squares): how much the figure would move with other releases of the same kind. NaN with
  /// fewer than 2 releases measuring the component.
  std::array<double, kForceComponents> heldout_se{};
  std::size_t releases = 0;  ///< releases with a history
  std::size_t samples = 0;   ///< contact samples per evaluation
};

/// The error of `model` (the assessment's model: parameters in its order) along `histories`
/// (aligned with the set `a` was made on). In-sample: at a.population.params; held-out: over
/// every split of a.cv, at a.fold_params[split] on that split's test releases, pooled over the
/// repeats (a split with its own model, Assessment::fold_models, at that model). Throws
/// std::invalid_argument when the sizes disagree.
ForceHistoryError force_history_error(const Model& model, const Shape& shape, const Assessment& a,
                                      const std::vector<std::optional<MeasuredHistory>>& histories,
                                      const EngineOptions& engine = {});

/// Each release's own calibration (the diagnosis's per-release fits, model order), aligned with
/// a set of `releases`; empty when `d` has no per-release fits of that set.
std::vector<std::vector<double>> release_params_of(const Diagnosis& d, std::size_t releases);

/// The force law the diagnosed model leaves on the histories `data` keeps (force_law_from_tracks):
/// each release at its own per-release fit where `d` has them (so that the constants'
/// release-to-release scatter is not read as a force), else at the population fit. nullopt
/// when `data` keeps fewer than two histories of the set's releases.
std::optional<ForceLawReport> force_law_of(const Diagnosis& d, const std::string& data,
                                           const ImpactSet& set, const Shape& shape,
                                           const Model& model, const EngineOptions& engine = {});

/// force_history_error of every rung of `l` (rung_model(base, l, r)), or nothing when fewer than
/// two releases have a history (`ladder`'s force_history).
std::vector<ForceHistoryError> ladder_force_history(
    const Model& base, const Ladder& l, const Shape& shape,
    const std::vector<std::optional<MeasuredHistory>>& histories, const EngineOptions& engine = {});

/// The standard error of an RMS pooled over releases, sqrt(sum ss_i / sum n_i), from each
/// release's sum of squares ss_i and sample count n_i (releases with n_i = 0 are skipped): the
/// ratio estimator's variance over releases, (m / (m - 1)) sum (ss_i - R n_i)^2 / (sum n_i)^2
/// with R = sum ss_i / sum n_i (Cochran 1977, Sampling Techniques, 3rd ed., eq. 6.9, the
/// releases as clusters of samples), taken to the RMS by the delta method (SE / (2 sqrt R)).
/// With equal n_i it is the textbook standard error of the mean of the releases' mean squares,
/// so carried. NaN with fewer than 2 releases or R = 0. Throws std::invalid_argument when the
/// sizes differ.
double pooled_rms_se(std::span<const double> ss, std::span<const std::size_t> n);

/// JSON: insample_rms, heldout_rms, heldout_se (objects by component: normal [N], tangential
/// [N], moment [N m]; null where not measured), releases, samples.
nlohmann::json to_json(const ForceHistoryError& e);

/// The force histories' replicate floor (issue 33, item 4: "within 2 x the replicate floor ...
/// on the force histories"): how far one measured history lies from the mean history of its
/// replicates (same replicate label or incident state, replicate_groups), the part of the
/// force-history error no deterministic model can remove. Each history is aligned at its
/// contact's start (stats::contact_window, the contact rule of `ricochet stats`: the run of
/// records around the peak whose force exceeds 0.2 block weights) and read on a grid of its
/// group's record interval from there to the end of the group's longest contact, its own
/// measured values where it has records and 0 beyond them (in flight). Per component, the
/// pooled within-group variance over every grid time and group, sum of (value - group mean)^2
/// over sum of (members - 1), as a root mean square: the normal force F_y and the tangential
/// force F_x [N] (the contact frame on flat ground) and the moment about the block's lowest
/// point [N m] (torque - r x F, r that point relative to the centroid: the point the
/// force-history error's moment is taken about on flat ground, up to half the penetration).
struct ForceHistoryScatter {
  std::array<double, kForceComponents> rms{};  ///< N, N, N m; NaN without two measured members
  std::size_t groups = 0;                      ///< replicate groups with two histories or more
  std::size_t histories = 0;                   ///< histories in those groups
  std::size_t samples = 0;                     ///< grid times summed over the groups
  std::string source;  ///< the file a borrowed floor comes from ("" for a set's own)
  std::string where;   ///< the filter its releases were chosen by ("" = all of the shape)
};

/// force_history_scatter of `set`'s replicate groups, `histories` aligned with set.impacts
/// (measured_histories); groups = 0 and NaN when no group has two histories. Throws
/// std::invalid_argument when the sizes disagree.
ForceHistoryScatter force_history_scatter(
    const ImpactSet& set, const std::vector<std::optional<MeasuredHistory>>& histories,
    const Shape& shape);

/// JSON: rms (object by component, null where not measured), groups, histories, samples,
/// source, moment_about ("the block's lowest point").
nlohmann::json to_json(const ForceHistoryScatter& s);

/// `base` at `base_params` (model order) plus a `term_<name>` effect for every term the report
/// selected, at its discovered coefficient and not calibrated (the histories identify it; a
/// recalibration on rebounds would move it where the rebounds cannot tell, e.g. a drag of 981
/// kg/m for a true 40: docs/diagnosis.md). A coefficient outside its effect's bounds (a negative
/// drag: effects/force_term.hpp) is clamped into them, with one line in *warnings saying so; a
/// term clamped to its neutral 0 is left out.
Model with_force_law(const Model& base, std::span<const double> base_params,
                     const ForceLawReport& report, std::vector<std::string>* warnings = nullptr);

/// The report's figure of a set with histories (issue 33, item 3): the residual normal force
/// (measured minus model) [N] against the time since each release's contact starts [ms], every
/// contact sample of every release with a history, before (`model`, each release at its own
/// calibration `release_params`, aligned with `histories`; `params` where an entry is empty)
/// and after the discovered law (`report`'s terms added by with_force_law), the RMS of each in
/// the caption. nullopt when fewer than two histories or the report adds no term.
std::optional<NamedFigure> force_residual_figure(
    const std::vector<std::optional<MeasuredHistory>>& histories, const Model& model,
    const Shape& shape, std::span<const double> params,
    const std::vector<std::vector<double>>& release_params, const ForceLawReport& report,
    const EngineOptions& engine, const std::string& title);

}  // namespace ricochet::diagnosis
