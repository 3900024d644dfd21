// Internal to the fit module (not installed): the pieces that the release fits (calibrate.cpp)
// and the population fits, predictions and held-out predictions (population.cpp) share.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"
#include "fit/fit.hpp"
#include "fit/optimize.hpp"
#include "impact/impact_set.hpp"

namespace ricochet::fit::detail {

// The calibrated parameters of a fit (calibration_model) as the variables of a unit box:
// linear between the bounds, or in log(value) for bounds spanning two decades (log_scaled).
struct ParameterBox {
  std::vector<std::size_t> index;
  std::vector<double> lo, hi;
  std::vector<char> log;

  // `allow_empty`: a model with no calibrated parameter is a box of size 0 (a population fit
  // then evaluates the model as it is) instead of an error.
  ParameterBox(const Model& model, const ErrorOptions& error, bool allow_empty = false) {
    index = calibration_model(model, error).calibrated_indices();
    if (index.empty() && !allow_empty)
      throw std::invalid_argument("the model has no calibrated parameter (model file `calibrate`)");
    for (std::size_t i : index) {
      lo.push_back(model.lower(i));
      hi.push_back(model.upper(i));
      log.push_back(log_scaled(model.lower(i), model.upper(i)) ? 1 : 0);
    }
  }
  std::size_t size() const { return index.size(); }
  double to_value(std::size_t k, double u) const {
    if (log[k]) return lo[k] * std::pow(hi[k] / lo[k], u);
    return lo[k] + (hi[k] - lo[k]) * u;
  }
  double to_unit(std::size_t k, double v) const {
    if (!(hi[k] > lo[k])) return 0.0;
    const double u = log[k] ? std::log(std::max(v, lo[k]) / lo[k]) / std::log(hi[k] / lo[k])
                            : (v - lo[k]) / (hi[k] - lo[k]);
    return std::clamp(u, 0.0, 1.0);
  }
};

// How the orientation of one release is set.
struct AlphaPlan {
  std::string source;         // "none", "data", "fitted", "marginal"
  std::vector<double> fixed;  // orientations averaged over (one value unless marginal)
  bool fitted = false;
};

// `points`: the size of the rule of a marginal release (AlphaOptions::marginal_points for a
// population search, prediction_points() otherwise).
AlphaPlan plan_alpha(const Shape& shape, const Impact& impact, const AlphaOptions& a,
                     bool allow_fit, int points);

// Eq. 7 (with the optional contact terms of ErrorOptions), plus kFailedRebound when the engine
// saw no rebound.
double score(const CollisionResult& r, const Impact& impact, const ErrorOptions& options);

// Unit design of the start search: the model's own values first, then a Latin hypercube.
std::vector<double> start_design(const ParameterBox& box, const Model& model, std::size_t dim,
                                 const FitOptions& options);

// Engine settings of the merged lock-step batches: one thread (the caller parallelises over
// releases), lanes refilled from the queue so one long rebound does not hold a wide batch.
EngineOptions pool_engine(const FitOptions& options, int threads);

// Verified near-optimal points to seed the interval walks, row-major: the optimum first, then
// the other starts' end points and the design points within the threshold.
std::vector<double> near_points(const LocalResult& best, const std::vector<LocalResult>& ends,
                                const std::vector<double>& design, const std::vector<double>& f,
                                std::size_t dim, double threshold);

// Intervals of all variables of a solved problem. `inside` holds verified near-optimal points
// (row-major, at least the optimum). `alpha` describes the last variable when it is the
// orientation (window centred on `alpha_centre`).
std::vector<ParameterInterval> intervals_of(Problem& problem, const LocalResult& best,
                                            const Model& model, const ParameterBox& box,
                                            const AlphaOptions* alpha, double alpha_centre,
                                            double threshold, const FitOptions& options,
                                            std::vector<double> inside);

}  // namespace ricochet::fit::detail
