// Impact features and the trends of residuals and per-release calibrated parameters against
// them: the residual signatures of missing physics (each effect's Signature, docs/effects/).
//
// A trend is a Pearson correlation with its two-sided p-value (stats::pearson, OpenTURNS). Many
// trends are tested at once (every residual and parameter against every feature, about 40), so
// significance is decided over the family with Holm's step-down (stats::holm_adjust), which
// controls the family-wise error rate at TrendOptions::alpha: a trend is significant when its
// Holm-adjusted Pearson p AND its Holm-adjusted Spearman p (the Pearson correlation of the ranks,
// ties averaged) are below alpha with the same sign: one outlying release (lab cylinder C12)
// must not make a trend on its own. residual_trends() and parameter_trends() control their own
// family; control_family() re-decides over a union (compare() does it over both). Features that the
// set does not measure (penetration, contact duration, alpha_in of the lab data) are replaced by
// the calibrated model's simulated values, and named so ("penetration (simulated)"): a trend
// against a simulated feature is a trend against what the model thinks happened.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "diagnosis/assess.hpp"
#include "fit/fit.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::diagnosis {

/// One feature of every release of a set.
struct Feature {
  std::string name;  ///< key: a word of the signature vocabulary (feature_name, effect.hpp)
  std::string
      label;  ///< for text and figures, e.g. "|V_in^y| [m/s]", "penetration (simulated) [m]"
  bool simulated = false;  ///< from the calibrated model, not measured
  std::vector<double> values;
};

/// Features of a set. `insample`: predictions of the calibrated model (for the simulated
/// penetration and duration when the set lacks them); `alpha_fitted`: per-release fitted
/// orientations (NaN where none), used when the set lacks alpha_in.
std::vector<Feature> impact_features(const ImpactSet& set,
                                     const std::vector<ObsPrediction>& insample,
                                     const std::vector<double>& alpha_fitted = {});

/// The quantity of the residual trends of observable k (kObsVx, ...): "residual vy", a word of
/// the signature vocabulary (quantity_name, effects/effect.hpp).
std::string residual_quantity(int observable);
/// The quantity of the per-release trends of the calibrated parameter `name`: "param en2".
std::string parameter_quantity(const std::string& name);

/// One correlation.
struct Trend {
  std::string quantity;  ///< residual_quantity() or parameter_quantity(), e.g. "param en2"
  std::string label;     ///< "V_out^y residual", "calibrated en2"
  std::string feature;   ///< Feature::name
  std::string feature_label;
  double r = 0, p = 1;                 ///< Pearson
  double rho = 0, p_rank = 1;          ///< Spearman
  double p_holm = 1, p_rank_holm = 1;  ///< Holm-adjusted over the family
  std::size_t n = 0;
  bool significant = false;
};

struct TrendOptions {
  double alpha = 0.05;  ///< family-wise error rate of the trend tests (Holm)
};

/// Trends of each observable's residual (measured - predicted) against each feature.
std::vector<Trend> residual_trends(const ErrorReport& report,
                                   const std::array<bool, kObservables>& use,
                                   const std::vector<Feature>& features,
                                   const TrendOptions& options = {});

/// Trends of each per-release calibrated parameter against each feature, over the releases
/// where the parameter is identified (fit::Identifiability::kIdentified), or all releases when
/// no interval was computed.
std::vector<Trend> parameter_trends(const std::vector<fit::ReleaseFit>& fits,
                                    const std::vector<Feature>& features,
                                    const TrendOptions& options = {});

/// Decides `significant` over the union of `groups` (Holm, family-wise level alpha).
void control_family(const std::vector<std::vector<Trend>*>& groups, double alpha);

/// The trend of `quantity` against `feature` in `trends`, or nullptr.
const Trend* find_trend(const std::vector<Trend>& trends, const std::string& quantity,
                        const std::string& feature);

/// "V_out^y residual falls with |V_in^y| (r = -0.82, p = 3e-06)"
std::string describe(const Trend& t);

nlohmann::json to_json(const Trend& t);
nlohmann::json to_json(const std::vector<Trend>& trends, bool significant_only);

}  // namespace ricochet::diagnosis
