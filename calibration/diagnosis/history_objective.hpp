// The force histories as a calibration target (issue 33): a term of the population fits'
// objective (fit::FitOptions::extra_objective) that measures how far the model's contact force
// along each fitted release's own measured path lies from the measured one, in units of the
// force histories' replicate floor, so that a fit reads the histories beside the rebounds.
//
// Why: on the stiff bed's verification the rebounds and the histories pull the friction law in
// opposite directions (docs/diagnosis.md, "Named laws, fitted on the histories"), and the
// rebounds alone do not pin a force coefficient (a drag anywhere in 0-981 kg/m for a true 40);
// a fit on both shows what a law can do on both at once.
//
// The term, for the releases being fitted (a fold fit's training releases only, so that a
// held-out release's history never enters the model it is judged with):
//   weight x sum over releases with a history of  mean over measured components c of
//   (RMS_c of measured minus model along the path / floor_c)^2
// in Eq. 7's units: weight = the set's V_out floor makes one force floor weigh as much as one
// rebound floor. The residual is force_residual's (the law's deepest slot in contact; moment
// about the contact point), the floor force_history_floor's.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "diagnosis/force_residual.hpp"
#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::diagnosis {

struct HistoryObjective {
  std::map<std::string, MeasuredHistory> histories;  ///< by release id
  std::array<double, kForceComponents> floor{};      ///< per component [N, N, N m]; NaN: unused
  double weight = 0;                                 ///< Eq. 7 units per (RMS / floor)^2
  Shape shape;
  EngineOptions engine;  ///< of the path force (dt, ground)

  /// The term at `params` (model order) over the releases of `set` that have a history.
  double operator()(const Model& model, std::span<const double> params, const ImpactSet& set) const;
};

/// The objective of `histories` (aligned with `set`, measured_histories; releases without one
/// are skipped) against `floor`. Throws InputError (field `option`) for a weight that is not
/// positive and finite, or a floor without one positive finite component.
std::shared_ptr<const HistoryObjective> history_objective(
    const ImpactSet& set, const std::vector<std::optional<MeasuredHistory>>& histories,
    const std::array<double, kForceComponents>& floor, double weight, const Shape& shape,
    const EngineOptions& engine, const std::string& option);

}  // namespace ricochet::diagnosis
