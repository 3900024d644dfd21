// Rival laws of a design of throws (issue 31, item 3): the base model alone ("none") or with
// one or two registered effects ("a", "a+b"), each calibrated on the set the way diagnose()
// calibrates its candidates (full-set population fit; fit::calibrate_population through the
// diagnosis's own steps, assess.hpp), never at a truth's values.
//
// Calibration, as assess() does on the full set (its held-out splits are not needed here):
//  - the base model as given: population fit with AssessOptions::population_starts BOBYQA runs
//    (contact_population_starts when penetration or contact duration enter the error, kn then
//    calibrated too: calibration_model_for);
//  - base + effects: warm-started from the base model's optimum with the effects at their
//    neutral values (Model::with_effect), warm_starts runs, then one local refinement within a
//    window of 0.15 of each range (refine_warm, windowed); the better fit wins.
#pragma once

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"

namespace ricochet::diagnosis {

/// One rival law, calibrated on the set.
struct Rival {
  std::string name;                  ///< "none", "a" or "a+b"
  std::vector<std::string> effects;  ///< the effects added to the base model (none: empty)
  /// calibration_model_for(base + effects) with its calibrated values: the model whose
  /// predictions and Jacobian the design uses.
  Model model;
  fit::PopulationFit fit;  ///< the population fit on the set
  /// The law as the diagnosis prints it (Effect::law with the calibrated values): the added
  /// effects'; for "none", the base model's own effects'.
  std::string law;
  double error = NAN;  ///< mean Eq. 7 (with the set's contact terms) per release at the optimum
};

/// The effects of each rival named in `names`: "none" (no effect), a registered effect, or
/// "a+b" (a pair). Throws InputError("<command line>", 0, option, ...) for an unknown effect
/// (listing the known ones), an effect already in the base model, a name given twice, or fewer
/// than two rivals.
std::vector<std::vector<std::string>> parse_rivals(std::span<const std::string> names,
                                                   const Model& base,
                                                   const EffectRegistry& registry,
                                                   const std::string& option = "--rivals");

/// The rival's name from its effects ("none", "a", "a+b").
std::string rival_name(const std::vector<std::string>& effects);

/// The base model calibrated on `set` ("none"), then every rival (file comment), in parallel
/// over rivals (one calibration per thread: the fits are deterministic, so the result does not
/// depend on the threads). `options` resolved on `set` (resolve_scale). Returns the base model
/// first, then the rivals in the order given ("none" among them is the base model again).
std::vector<Rival> calibrate_rivals(const Model& base, const Shape& shape, const ImpactSet& set,
                                    const std::vector<std::vector<std::string>>& rivals,
                                    const AssessOptions& options, const EffectRegistry& registry);

/// The rivals from a base model already calibrated on the set (`base`: name "none", its model
/// with the calibrated values and its population fit, e.g. the diagnosis's warm model), as
/// calibrate_rivals does after the base model's own fit. Returns the rivals in the order given
/// ("none" among them is `base` again). Throws std::runtime_error naming the first rival that
/// could not be calibrated.
std::vector<Rival> calibrate_rivals_from(const Rival& base, const Shape& shape,
                                         const ImpactSet& set,
                                         const std::vector<std::vector<std::string>>& rivals,
                                         const AssessOptions& options,
                                         const EffectRegistry& registry);

/// One rival's calibration: the rival, or why it could not be calibrated.
struct RivalCalibration {
  std::optional<Rival> rival;
  std::string error;  ///< the calibration's exception message when `rival` is empty
};

/// As calibrate_rivals_from, but a rival that cannot be calibrated does not stop the others:
/// its entry holds the reason instead (the diagnosis's second stage judges the others).
std::vector<RivalCalibration> try_calibrate_rivals_from(
    const Rival& base, const Shape& shape, const ImpactSet& set,
    const std::vector<std::vector<std::string>>& rivals, const AssessOptions& options,
    const EffectRegistry& registry);

/// The rivals when none are named: "none" plus, per family, the best member of the diagnosis's
/// confidence set of laws (diagnose() with `options`; Diagnosis::confidence_set).
std::vector<std::string> default_rivals(const Model& base, const Shape& shape, const ImpactSet& set,
                                        const DiagnoseOptions& options);

}  // namespace ricochet::diagnosis
