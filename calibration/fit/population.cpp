// Population fits (one parameter set for many releases, Eq. 7 summed), predictions and held-out
// predictions (fit.hpp); the release fits are in calibrate.cpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include "common/clock.hpp"
#include "common/error.hpp"
#include "fit/calibrate_internal.hpp"
#include "fit/collision_memo.hpp"
#include "fit/fibers.hpp"
#include "fit/fit.hpp"
#include "fit/optimize.hpp"
#include "fit/orientation_rule.hpp"
#include "fit/surrogate_search.hpp"

namespace ricochet::fit {

using detail::AlphaPlan;
using detail::intervals_of;
using detail::LocalResult;
using detail::near_points;
using detail::ParameterBox;
using detail::plan_alpha;
using detail::pool_engine;
using detail::Problem;
using detail::score;
using detail::start_design;

std::vector<Prediction> predict(const Model& model, const Shape& shape,
                                std::span<const double> params, const ImpactSet& set,
                                const FitOptions& options, std::span<const double> alpha_rad) {
  if (params.size() != model.parameter_count())
    throw std::invalid_argument("predict: " + std::to_string(params.size()) +
                                " parameter values for a model of " +
                                std::to_string(model.parameter_count()));
  if (!alpha_rad.empty() && alpha_rad.size() != set.size())
    throw std::invalid_argument("predict: alpha_rad must have one value per release");
  std::vector<Prediction> out(set.size());
  std::vector<CollisionCase> cases;
  std::vector<std::size_t> first(set.size() + 1, 0);
  for (std::size_t i = 0; i < set.size(); ++i) {
    const Impact& im = set.impacts[i];
    AlphaPlan plan;
    if (!shape.is_disc() && !im.alpha_in && !alpha_rad.empty() && std::isfinite(alpha_rad[i])) {
      plan.source = "given";
      plan.fixed = {alpha_rad[i]};
    } else {
      plan = plan_alpha(shape, im, options.alpha, false, options.alpha.prediction_points());
    }
    out[i].alpha_source = plan.source;
    out[i].alpha_rad = plan.fixed.size() == 1 && plan.source != "none" ? plan.fixed[0] : NAN;
    first[i] = cases.size();
    for (double a : plan.fixed) cases.push_back({im.vin, a});
  }
  first[set.size()] = cases.size();
  EngineOptions engine = options.engine;
  engine.threads = options.threads;
  const auto res = simulate_batch(model, shape, cases, params, engine);
  for (std::size_t i = 0; i < set.size(); ++i) {
    std::vector<double> at;
    const auto mean_of = [&](auto value) {
      at.clear();
      for (std::size_t c = first[i]; c < first[i + 1]; ++c) at.push_back(value(res[c]));
      return rule_mean(at);
    };
    Prediction& p = out[i];
    for (int k = 0; k < 3; ++k) {
      const RuleMean m = mean_of([k](const CollisionResult& r) { return r.vout[k]; });
      p.vout[k] = m.mean;
      p.vout_std[k] = std::sqrt(std::max(0.0, m.mean_sq - m.mean * m.mean));
      for (int h = 0; h < 2; ++h) {
        p.vout_half[h][k] = m.half[h];
        p.vout_std_half[h][k] = std::sqrt(std::max(0.0, m.half_sq[h] - m.half[h] * m.half[h]));
      }
      p.vout_quadrature_error[k] = m.error();
    }
    const RuleMean h = mean_of([](const CollisionResult& r) { return r.max_penetration_m; });
    const RuleMean t = mean_of([](const CollisionResult& r) { return r.contact_duration_s; });
    p.penetration_m = h.mean;
    p.contact_duration_s = t.mean;
    p.penetration_half_m = h.half;
    p.contact_duration_half_s = t.half;
    p.orientations = static_cast<int>(first[i + 1] - first[i]);
    int worst = 0;
    for (std::size_t c = first[i]; c < first[i + 1]; ++c)
      worst = std::max(worst, static_cast<int>(res[c].status));
    p.status = static_cast<CollisionStatus>(worst);
  }
  return out;
}

std::vector<double> prediction_errors(const ImpactSet& set,
                                      const std::vector<Prediction>& predictions,
                                      const ErrorOptions& options) {
  if (predictions.size() != set.size())
    throw std::invalid_argument("prediction_errors: one prediction per release expected");
  std::vector<double> e(set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    const auto c = contact_error_terms(predictions[i].penetration_m,
                                       predictions[i].contact_duration_s, set.impacts[i], options);
    e[i] = release_error(predictions[i].vout, set.impacts[i].vout, options) + c[0] + c[1];
  }
  return e;
}

namespace {

// Summed Eq. 7 over releases for one shared parameter vector. Every evaluation is one engine
// batch over the releases (and over the orientation grid of releases without alpha_in).
class PopulationProblem final : public Problem {
 public:
  // `points`: the orientation rule of marginal releases (search or polish rule).
  PopulationProblem(detail::Simulator& sim, const Model& model, const Shape& shape,
                    const ImpactSet& set, const FitOptions& options, const ParameterBox& box,
                    int points)
      : sim_(sim), model_(model), set_(set), options_(options), box_(box), base_(model.values()) {
    for (std::size_t i = 0; i < set.size(); ++i) {
      const AlphaPlan plan = plan_alpha(shape, set.impacts[i], options.alpha, false, points);
      marginal_ = marginal_ || plan.source == "marginal";
      for (double a : plan.fixed) {
        cases_.push_back({set.impacts[i].vin, a});
        owner_.push_back(i);
        weight_.push_back(1.0 / static_cast<double>(plan.fixed.size()));
      }
    }
  }
  std::size_t dim() const override { return box_.size(); }
  /// Whether some release is averaged over an orientation rule.
  bool marginal() const { return marginal_; }

  void params_of(const double* u, double* full) const {
    std::copy(base_.begin(), base_.end(), full);
    for (std::size_t k = 0; k < box_.size(); ++k) full[box_.index[k]] = box_.to_value(k, u[k]);
  }

  double eval(const std::vector<double>& u) override { return eval_many(u)[0]; }
  /// Through FitOptions::memo: the start design and the searches' first points, which every
  /// fold fit of an assessment shares (fit/collision_memo.hpp). The searches' later points are a
  /// fit's alone, and keeping them would cost memory for little reuse.
  std::vector<double> eval_starts(const std::vector<double>& points) override {
    return eval_batch(points, memo_ != nullptr);
  }
  std::vector<double> eval_many(const std::vector<double>& points) override {
    return eval_batch(points, false);
  }

  void parallel(std::vector<std::function<void()>>& tasks) override { sim_.parallel(tasks); }

  void set_memo(CollisionMemo* memo) { memo_ = memo; }

 private:
  // `shared`: through the memo.
  std::vector<double> eval_batch(const std::vector<double>& points, bool shared) {
    const std::size_t d = dim(), P = base_.size(), C = cases_.size();
    const std::size_t n = d == 0 ? 1 : points.size() / d;  // a fixed model: one point
    std::vector<CollisionCase> cases;
    cases.reserve(n * C);
    std::vector<double> params(n * C * P);
    std::vector<double> row(P);
    for (std::size_t i = 0; i < n; ++i) {
      params_of(points.data() + i * d, row.data());
      for (std::size_t c = 0; c < C; ++c) {
        cases.push_back(cases_[c]);
        std::copy(row.begin(), row.end(), params.begin() + (i * C + c) * P);
      }
    }
    const auto res = shared ? memo_->run(sim_, cases, params, P) : sim_.run(cases, params);
    evaluations += static_cast<int>(cases.size());
    std::vector<double> out(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < C; ++c)
        out[i] += weight_[c] * score(res[i * C + c], set_.impacts[owner_[c]], options_.error);
    if (options_.extra_objective)
      for (std::size_t i = 0; i < n; ++i)
        out[i] += options_.extra_objective(
            model_, std::span<const double>(params.data() + i * C * P, P), set_);
    return out;
  }

  detail::Simulator& sim_;
  const Model& model_;
  const ImpactSet& set_;
  const FitOptions& options_;
  const ParameterBox& box_;
  std::vector<double> base_;
  std::vector<CollisionCase> cases_;
  std::vector<std::size_t> owner_;
  std::vector<double> weight_;
  bool marginal_ = false;
  CollisionMemo* memo_ = nullptr;
};

}  // namespace

PopulationFit calibrate_population(const Model& model, const Shape& shape, const ImpactSet& set,
                                   const FitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  require_valid(options.problems(), "fit::calibrate_population");
  if (set.empty()) throw std::invalid_argument("calibrate_population: empty impact set");
  // A model with no calibrated parameter (model file `calibrate = []`: a law fixed elsewhere, e.g.
  // a resolved bed's upscaled one) is evaluated as it is: its "fit" is its error on the set.
  const ParameterBox box(model, options.error, true);
  const std::vector<double> design =
      box.size() > 0 ? start_design(box, model, box.size(), options) : std::vector<double>{};
  // Each evaluation is already a batch over releases; the pool merges the parallel searches'
  // batches and spreads them over the threads.
  detail::FiberPool pool(model, shape,
                         pool_engine(options, options.threads > 0 ? options.threads : 0));
  PopulationProblem search(pool, model, shape, set, options, box, options.alpha.marginal_points);
  // The refined rule (AlphaOptions::polish_points): the search's best ends are polished on it, and
  // the intervals are walked on it. Without marginal releases, or without a distinct rule, the
  // search's problem is the fit's.
  const int fine_points = options.alpha.prediction_points();
  std::optional<PopulationProblem> fine;
  if (search.marginal() && fine_points != options.alpha.marginal_points)
    fine.emplace(pool, model, shape, set, options, box, fine_points);
  PopulationProblem& problem = fine ? *fine : search;
  // The response surface needs the refined rule and a design to interpolate (OrientationSearch).
  const bool surface = options.alpha.search == OrientationSearch::kSurface && fine &&
                       box.size() > 0 && design.size() / box.size() > 2 * box.size();
  // A memo of another model (a split's own model, with other effects), shape or engine setting
  // is not used.
  CollisionMemo* memo =
      options.memo && options.memo->scope() == collision_memo_scope(model, shape, options.engine)
          ? options.memo.get()
          : nullptr;
  search.set_memo(memo);
  if (fine) fine->set_memo(memo);
  std::vector<LocalResult> surface_points;
  PopulationFit fit;
  fit.names = model.parameter_names();
  fit.calibrated = box.index;
  pool.spawn([&] {
    std::vector<double> design_values;
    std::vector<LocalResult> ends;
    LocalResult best;
    if (box.size() == 0) {
      best.f = problem.eval({});
      ends.push_back(best);
    } else if (surface) {
      // Every collision on the refined rule (OrientationSearch::kSurface): the design, the
      // surface's rounds, then a BOBYQA polish of the best point.
      design_values = problem.eval_starts(design);
      detail::SurrogateSearchOptions so;
      so.starts = options.starts;
      so.rounds = options.alpha.surface_rounds;
      std::vector<LocalResult> evaluated;
      best = detail::surrogate_search(problem, design, design_values, so, evaluated);
      best = detail::polish(problem, {best}, 1, options.xtol, options.max_evaluations, ends);
      // The evaluated points stand in for the design: the intervals start from those inside.
      surface_points = std::move(evaluated);
    } else {
      // The search only has to find the basins the polish refines (AlphaOptions::search_xtol).
      best = detail::multi_start(search, design, options.starts,
                                 fine ? options.alpha.search_xtol : options.xtol,
                                 options.max_evaluations, ends, design_values);
    }
    if (fine && box.size() > 0 && !surface) {
      // The model's own values (the design's first point) are a candidate too: a warm start
      // (a fold's optimum polished on the full set) is already near a minimum of the fine rule,
      // which the search rule's BOBYQA run may leave.
      std::vector<LocalResult> from = ends;
      from.push_back(best);
      from.push_back({std::vector<double>(design.begin(), design.begin() + box.size()),
                      design_values.empty() ? best.f : design_values[0]});
      best = detail::polish(*fine, std::move(from), options.alpha.polish_ends, options.xtol,
                            options.max_evaluations, ends);
    }
    for (const auto& e : ends) fit.start_errors.push_back(e.f);
    fit.params = model.values();
    problem.params_of(best.u.data(), fit.params.data());
    fit.error = best.f;
    double sum_delta = 0;
    for (const auto& im : set.impacts)
      sum_delta +=
          noise_threshold(im.vout, im.sigma_vout ? *im.sigma_vout : options.sigma, options.error) +
          contact_noise_threshold(im, options.sigma_penetration_m, options.sigma_contact_duration_s,
                                  options.error);
    // Mean per-release Delta (3 degrees of freedom), inflated by the reduced chi-square when
    // the releases scatter more than the noise (see fit.hpp).
    fit.threshold = options.threshold_scale * sum_delta / static_cast<double>(set.size()) *
                    std::max(1.0, best.f / sum_delta);
    if (options.intervals && box.size() > 0) {
      const double limit = best.f + fit.threshold;
      // Only points evaluated on the interval's own rule are verified: a polished fit's design
      // was scored on the search rule.
      std::vector<double> inside =
          fine ? near_points(best, ends, {}, {}, box.size(), limit)
               : near_points(best, ends, design, design_values, box.size(), limit);
      for (const auto& p : surface_points)
        if (p.f <= limit) inside.insert(inside.end(), p.u.begin(), p.u.end());
      fit.intervals =
          intervals_of(problem, best, model, box, nullptr, 0.0, limit, options, std::move(inside));
    }
  });
  pool.run_all();
  fit.predictions = predict(model, shape, fit.params, set, options);
  fit.release_errors = prediction_errors(set, fit.predictions, options.error);
  fit.evaluations = search.evaluations + (fine ? fine->evaluations : 0);
  fit.seconds = seconds_since(t0);
  return fit;
}

HeldOut heldout_predictions(const Model& model, const Shape& shape, const ImpactSet& set,
                            std::size_t folds, const FitOptions& options) {
  require_valid(options.problems(), "fit::heldout_predictions");
  if (folds < 2 || folds > set.size())
    throw std::invalid_argument("heldout_predictions: folds must be in [2, number of releases]");
  HeldOut out;
  out.predictions.resize(set.size());
  out.errors.resize(set.size());
  FitOptions o = options;
  o.intervals = false;
  for (std::size_t f = 0; f < folds; ++f) {
    ImpactSet train = set, test = set;
    train.impacts.clear();
    test.impacts.clear();
    std::vector<std::size_t> test_index;
    for (std::size_t i = 0; i < set.size(); ++i) {
      if (i % folds == f) {
        test.impacts.push_back(set.impacts[i]);
        test_index.push_back(i);
      } else {
        train.impacts.push_back(set.impacts[i]);
      }
    }
    const PopulationFit pf = calibrate_population(model, shape, train, o);
    out.fold_params.push_back(pf.params);
    const auto pred = predict(model, shape, pf.params, test, o);
    const auto err = prediction_errors(test, pred, o.error);
    for (std::size_t k = 0; k < test_index.size(); ++k) {
      out.predictions[test_index[k]] = pred[k];
      out.errors[test_index[k]] = err[k];
    }
  }
  return out;
}

}  // namespace ricochet::fit
