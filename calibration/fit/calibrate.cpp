#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "common/clock.hpp"
#include "common/error.hpp"
#include "fit/calibrate_internal.hpp"
#include "fit/design.hpp"
#include "fit/fibers.hpp"
#include "fit/fit.hpp"
#include "fit/optimize.hpp"
#include "fit/orientation_rule.hpp"

namespace ricochet::fit {

using detail::AlphaPlan;
using detail::intervals_of;
using detail::near_points;
using detail::ParameterBox;
using detail::plan_alpha;
using detail::pool_engine;
using detail::score;
using detail::start_design;

const char* alpha_mode_name(AlphaMode mode) {
  return mode == AlphaMode::kFit ? "fit" : "marginal";
}

const char* orientation_search_name(OrientationSearch search) {
  return search == OrientationSearch::kSurface ? "surface" : "multistart";
}

OrientationSearch orientation_search_from(const std::string& name) {
  constexpr OrientationSearch kAll[] = {OrientationSearch::kMultiStart,
                                        OrientationSearch::kSurface};
  for (OrientationSearch s : kAll)
    if (name == orientation_search_name(s)) return s;
  throw std::invalid_argument("'" + name + "': use " + orientation_search_name(kAll[0]) + " or " +
                              orientation_search_name(kAll[1]));
}

const char* identifiability_name(Identifiability status) {
  switch (status) {
    case Identifiability::kIdentified:
      return "identified";
    case Identifiability::kLowerBoundOnly:
      return "lower_bound_only";
    case Identifiability::kUpperBoundOnly:
      return "upper_bound_only";
    case Identifiability::kNotIdentified:
      return "not_identified";
  }
  return "?";
}

bool uses_contact_terms(const ErrorOptions& error) {
  return error.penetration || error.contact_duration;
}

ErrorOptions with_contact_terms(const ErrorOptions& error, const ImpactSet& set) {
  ErrorOptions e = error;
  e.penetration = e.contact_duration = !set.empty();
  double mean_h = 0, mean_t = 0;
  for (const auto& im : set.impacts) {
    e.penetration = e.penetration && im.penetration.has_value();
    e.contact_duration = e.contact_duration && im.contact_duration.has_value();
    mean_h += im.penetration.value_or(0.0) / static_cast<double>(set.size());
    mean_t += im.contact_duration.value_or(0.0) / static_cast<double>(set.size());
  }
  // One constant denominator per contact term (ErrorOptions, fit/error.hpp), unless one was
  // already decided.
  if (e.penetration && !(e.penetration_scale_m > 0))
    e.penetration_scale_m = std::max(mean_h, e.penetration_floor_m);
  if (e.contact_duration && !(e.contact_duration_scale_s > 0))
    e.contact_duration_scale_s = std::max(mean_t, e.contact_duration_floor_s);
  return e;
}

Model calibration_model(const Model& model, const ErrorOptions& error) {
  Model m = model;
  if (!uses_contact_terms(error)) return m;
  for (std::size_t i = 0; i < model.parameter_count(); ++i)
    if (model.spec(i).identified_by == IdentifiedBy::kContactFeatures && !model.held(i))
      m.set_calibrated(model.spec(i).name, true);
  return m;
}

bool log_scaled(double lower, double upper) {
  return lower > 0 && upper >= 100.0 * lower;
}

double ReleaseFit::value(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return params[i];
  throw std::invalid_argument("release fit has no parameter '" + name + "'");
}

const ParameterInterval* ReleaseFit::interval(const std::string& name) const {
  for (const auto& iv : intervals)
    if (iv.name == name) return &iv;
  if (alpha_interval && alpha_interval->name == name) return &*alpha_interval;
  return nullptr;
}

namespace {

using detail::LocalResult;
using detail::Problem;

// Eq. 7 of one release as a function of the unit box (calibrated parameters, then the
// orientation when it is a fitted nuisance).
class ReleaseProblem final : public Problem {
 public:
  ReleaseProblem(detail::Simulator& sim, const Model& model, const Impact& impact,
                 const FitOptions& options, const ParameterBox& box, const AlphaPlan& alpha)
      : sim_(sim),
        impact_(impact),
        options_(options),
        box_(box),
        alpha_(alpha),
        base_(model.values()),
        alpha_centre_(0.5 * (options.alpha.min_rad + options.alpha.max_rad)) {}

  std::size_t dim() const override { return box_.size() + (alpha_.fitted ? 1 : 0); }

  // The orientation window is one symmetry period wide and periodic: u = 0.5 is its centre.
  double alpha_of(const std::vector<double>& u) const {
    return alpha_centre_ + alpha_period() * (u[box_.size()] - 0.5);
  }
  double alpha_period() const { return options_.alpha.max_rad - options_.alpha.min_rad; }
  /// Re-centres the window on `centre` (the fitted angle), so that the interval walk can go a
  /// full half period either way; returns the shift to add to every u (modulo 1).
  double recentre_alpha(double centre) {
    const double shift = (alpha_centre_ - centre) / alpha_period();
    alpha_centre_ = centre;
    return shift;
  }

  void params_of(const double* u, double* full) const {
    std::copy(base_.begin(), base_.end(), full);
    for (std::size_t k = 0; k < box_.size(); ++k) full[box_.index[k]] = box_.to_value(k, u[k]);
  }

  double eval(const std::vector<double>& u) override { return eval_many(u)[0]; }

  std::vector<double> eval_many(const std::vector<double>& points) override {
    const std::size_t d = dim();
    const std::size_t n = points.size() / d;
    const std::size_t P = base_.size();
    const std::size_t per = alpha_.fitted ? 1 : alpha_.fixed.size();
    std::vector<CollisionCase> cases(n * per);
    std::vector<double> params(n * per * P);
    for (std::size_t i = 0; i < n; ++i) {
      const std::vector<double> u(points.begin() + i * d, points.begin() + (i + 1) * d);
      for (std::size_t a = 0; a < per; ++a) {
        CollisionCase& c = cases[i * per + a];
        c.vin = impact_.vin;
        c.alpha_rad = alpha_.fitted ? alpha_of(u) : alpha_.fixed[a];
        params_of(u.data(), params.data() + (i * per + a) * P);
      }
    }
    const auto res = sim_.run(cases, params);
    evaluations += static_cast<int>(cases.size());
    std::vector<double> out(n);
    for (std::size_t i = 0; i < n; ++i) {
      Vel3 mean{};
      double err = 0;
      int worst = 0;
      for (std::size_t a = 0; a < per; ++a) {
        const CollisionResult& r = res[i * per + a];
        // Marginal mode: the expected Eq. 7 over orientations.
        err += score(r, impact_, options_.error) / static_cast<double>(per);
        for (int k = 0; k < 3; ++k) mean[k] += r.vout[k] / static_cast<double>(per);
        worst = std::max(worst, static_cast<int>(r.status));
      }
      out[i] = err;
      last_vout_ = mean;
      last_status_ = static_cast<CollisionStatus>(worst);
    }
    return out;
  }

  void parallel(std::vector<std::function<void()>>& tasks) override { sim_.parallel(tasks); }

  /// V_out (mean over orientations in marginal mode) and engine status at u.
  Vel3 vout(const std::vector<double>& u, CollisionStatus& status) {
    eval(u);
    status = last_status_;
    return last_vout_;
  }

 private:
  detail::Simulator& sim_;
  const Impact& impact_;
  const FitOptions& options_;
  const ParameterBox& box_;
  const AlphaPlan& alpha_;
  std::vector<double> base_;
  double alpha_centre_;
  Vel3 last_vout_{};
  CollisionStatus last_status_ = CollisionStatus::kOk;
};

// `value_of` maps a unit coordinate to the parameter's value (ParameterBox::to_value).
template <class ValueOf>
ParameterInterval make_interval(const std::string& name, const std::string& unit, double lo,
                                double hi, double value, const detail::UnitInterval& ui,
                                const ValueOf& value_of) {
  ParameterInterval iv;
  iv.name = name;
  iv.unit = unit;
  iv.bound_lo = lo;
  iv.bound_hi = hi;
  iv.value = value;
  iv.lo = value_of(ui.lo);
  iv.hi = value_of(ui.hi);
  iv.lo_at_bound = ui.lo_at_bound;
  iv.hi_at_bound = ui.hi_at_bound;
  for (const auto& p : ui.profile) iv.profile.push_back({value_of(p[0]), p[1]});
  return iv;
}

// Whether the objective at the optimum is unchanged when variable j moves to its upper bound
// (the parameter's cap is never reached there): used to explain an unidentified upper side.
bool insensitive_up(Problem& problem, const LocalResult& best, std::size_t j, double resolution) {
  if (best.u[j] >= 1.0 - resolution) return false;  // nothing to compare with
  std::vector<double> u = best.u;
  u[j] = 1.0;
  const double f = problem.eval(u);
  return std::fabs(f - best.f) <= 1e-9 * std::max(1.0, std::fabs(best.f));
}

// The orientation is periodic: an arc short of the full period is identified (whichever window
// side it touches); the full period is not.
void classify_angle(ParameterInterval& iv) {
  const double deg = 180.0 / M_PI;
  char buf[200];
  if (iv.lo_at_bound && iv.hi_at_bound) {
    iv.status = Identifiability::kNotIdentified;
    std::snprintf(buf, sizeof buf,
                  "alpha_in not identified: every orientation fits within the noise threshold");
  } else {
    iv.status = Identifiability::kIdentified;
    std::snprintf(buf, sizeof buf,
                  "alpha_in in [%.3g, %.3g] rad ([%.0f, %.0f] deg, modulo %.0f deg)", iv.lo, iv.hi,
                  iv.lo * deg, iv.hi * deg, (iv.bound_hi - iv.bound_lo) * deg);
  }
  iv.statement = buf;
}

}  // namespace

namespace detail {

// `points`: the size of the rule of a marginal release (AlphaOptions::marginal_points for a
// population search, prediction_points() otherwise).
AlphaPlan plan_alpha(const Shape& shape, const Impact& impact, const AlphaOptions& a,
                     bool allow_fit, int points) {
  AlphaPlan p;
  if (shape.is_disc()) {
    p.source = "none";
    p.fixed = {0.0};
  } else if (impact.alpha_in) {
    p.source = "data";
    p.fixed = {*impact.alpha_in};
  } else if (a.mode == AlphaMode::kFit && allow_fit) {
    p.source = "fitted";
    p.fitted = true;
  } else {
    p.source = "marginal";
    p.fixed = orientation_rule(a, points, a.rotate ? release_rotation(impact.id) : 0.5);
  }
  return p;
}

// Eq. 7 (with the optional contact terms of ErrorOptions), plus kFailedRebound when the engine
// saw no rebound.
double score(const CollisionResult& r, const Impact& impact, const ErrorOptions& options) {
  const auto c = contact_error_terms(r.max_penetration_m, r.contact_duration_s, impact, options);
  return release_error(r.vout, impact.vout, options) + c[0] + c[1] +
         (r.status == CollisionStatus::kOk ? 0.0 : kFailedRebound);
}

// Unit design of the start search: the model's own values first, then a Latin hypercube.
std::vector<double> start_design(const ParameterBox& box, const Model& model, std::size_t dim,
                                 const FitOptions& options) {
  std::vector<double> design(dim, 0.5);  // alpha (if any) starts at the middle of its range
  for (std::size_t k = 0; k < box.size(); ++k)
    design[k] = box.to_unit(k, model.values()[box.index[k]]);
  if (options.design_points < 0) return design;  // a local refinement of the model's values
  const std::size_t n =
      options.design_points > 0 ? static_cast<std::size_t>(options.design_points) : 16 * dim;
  const std::vector<double> lhs = lhs_unit_design(dim, n, options.seed);
  design.insert(design.end(), lhs.begin(), lhs.end());
  return design;
}

// Engine settings of the merged lock-step batches: one thread (the caller parallelises over
// releases), lanes refilled from the queue so one long rebound does not hold a wide batch.
EngineOptions pool_engine(const FitOptions& options, int threads) {
  EngineOptions e = options.engine;
  e.threads = threads;
  e.lanes = std::min<std::size_t>(e.lanes, 16);
  return e;
}

// Verified near-optimal points to seed the interval walks, row-major: the optimum first, then
// the other starts' end points and the design points within the threshold.
std::vector<double> near_points(const LocalResult& best, const std::vector<LocalResult>& ends,
                                const std::vector<double>& design, const std::vector<double>& f,
                                std::size_t dim, double threshold) {
  std::vector<double> out = best.u;
  for (const auto& e : ends)
    if (e.f <= threshold) out.insert(out.end(), e.u.begin(), e.u.end());
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f[i] <= threshold)
      out.insert(out.end(), design.begin() + i * dim, design.begin() + (i + 1) * dim);
  return out;
}

// Intervals of all variables of a solved problem. `inside` holds verified near-optimal points
// (row-major, at least the optimum). `alpha` describes the last variable when it is the
// orientation (window centred on `alpha_centre`).
std::vector<ParameterInterval> intervals_of(Problem& problem, const LocalResult& best,
                                            const Model& model, const ParameterBox& box,
                                            const AlphaOptions* alpha, double alpha_centre,
                                            double threshold, const FitOptions& options,
                                            std::vector<double> inside) {
  std::vector<ParameterInterval> out;
  const std::size_t d = problem.dim();
  const std::vector<detail::UnitInterval> uis = detail::near_optimal_intervals(
      problem, best, threshold, options.interval_resolution, inside, options.xtol);
  for (std::size_t j = 0; j < d; ++j) {
    const detail::UnitInterval& ui = uis[j];
    ParameterInterval iv;
    if (j < box.size()) {
      const ParameterSpec& s = model.spec(box.index[j]);
      iv = make_interval(std::string(s.name), std::string(s.unit), box.lo[j], box.hi[j],
                         box.to_value(j, best.u[j]), ui,
                         [&](double u) { return box.to_value(j, u); });
    } else {
      const double half = 0.5 * (alpha->max_rad - alpha->min_rad);
      const double lo = alpha_centre - half, hi = alpha_centre + half;
      iv = make_interval("alpha_in", "rad", lo, hi, alpha_centre, ui,
                         [&](double u) { return lo + (hi - lo) * u; });
    }
    if (j < box.size())
      detail::classify(
          iv, ui.hi_at_bound && insensitive_up(problem, best, j, options.interval_resolution),
          model.spec(box.index[j]).role);
    else
      classify_angle(iv);
    out.push_back(std::move(iv));
  }
  return out;
}

}  // namespace detail

namespace {

// One release's calibration, drawing collisions from `sim` (file comment of fit.hpp).
ReleaseFit fit_release(detail::Simulator& sim, const Model& model, const Shape& shape,
                       const Impact& impact, const FitOptions& options,
                       const std::vector<double>& design) {
  const auto t0 = std::chrono::steady_clock::now();
  const ParameterBox box(model, options.error);
  const AlphaPlan alpha =
      plan_alpha(shape, impact, options.alpha, true, options.alpha.prediction_points());
  ReleaseProblem problem(sim, model, impact, options, box, alpha);
  const std::size_t d = problem.dim();

  ReleaseFit fit;
  fit.id = impact.id;
  fit.names = model.parameter_names();
  fit.calibrated = box.index;
  fit.measured = impact.vout;
  fit.alpha_source = alpha.source;

  std::vector<double> design_values;
  std::vector<LocalResult> ends;
  const LocalResult best = detail::multi_start(problem, design, options.starts, options.xtol,
                                               options.max_evaluations, ends, design_values);
  for (const auto& e : ends) fit.start_errors.push_back(e.f);
  fit.params = model.values();
  problem.params_of(best.u.data(), fit.params.data());
  fit.error = best.f;
  fit.simulated = problem.vout(best.u, fit.status);
  fit.terms = release_error_terms(fit.simulated, impact.vout, options.error);
  if (alpha.fitted)
    fit.alpha_rad = problem.alpha_of(best.u);
  else if (alpha.source == "data")
    fit.alpha_rad = alpha.fixed[0];

  const Vel3 sigma = impact.sigma_vout ? *impact.sigma_vout : options.sigma;
  fit.threshold = options.threshold_scale *
                  (noise_threshold(impact.vout, sigma, options.error) +
                   contact_noise_threshold(impact, options.sigma_penetration_m,
                                           options.sigma_contact_duration_s, options.error));
  if (options.intervals) {
    const double limit = best.f + fit.threshold;
    std::vector<double> inside = near_points(best, ends, design, design_values, d, limit);
    LocalResult centred = best;
    if (alpha.fitted) {
      // Periodic orientation: centre the window on the fitted angle, move the points with it.
      const double shift = problem.recentre_alpha(fit.alpha_rad);
      for (std::size_t i = 0; (i + 1) * d <= inside.size(); ++i) {
        double& u = inside[i * d + d - 1];
        u = u + shift - std::floor(u + shift);
      }
      centred.u[d - 1] = 0.5;
      inside[d - 1] = 0.5;
    }
    auto ivs = intervals_of(problem, centred, model, box, &options.alpha, fit.alpha_rad, limit,
                            options, std::move(inside));
    if (alpha.fitted) {
      fit.alpha_interval = ivs.back();
      ivs.pop_back();
    }
    fit.intervals = std::move(ivs);
  }
  fit.evaluations = problem.evaluations;
  fit.seconds = seconds_since(t0);
  return fit;
}

std::size_t design_dim(const Model& model, const Shape& shape, const Impact& impact,
                       const FitOptions& options) {
  return ParameterBox(model, options.error).size() +
         (plan_alpha(shape, impact, options.alpha, true, 1).fitted ? 1 : 0);
}

}  // namespace

ReleaseFit calibrate_release(const Model& model, const Shape& shape, const Impact& impact,
                             const FitOptions& options) {
  require_valid(options.problems(), "fit::calibrate_release");
  const ParameterBox box(model, options.error);
  const std::vector<double> design =
      start_design(box, model, design_dim(model, shape, impact, options), options);
  detail::FiberPool pool(model, shape, pool_engine(options, 1));
  ReleaseFit fit;
  pool.spawn([&] { fit = fit_release(pool, model, shape, impact, options, design); });
  pool.run_all();
  return fit;
}

std::vector<ReleaseFit> calibrate_releases(const Model& model, const Shape& shape,
                                           const ImpactSet& set, const FitOptions& options,
                                           const ReleaseHooks& hooks) {
  require_valid(options.problems(), "fit::calibrate_releases");
  const ParameterBox box(model, options.error);  // validates the model before threads start
  std::vector<ReleaseFit> out(set.size());
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < set.size(); ++i)
    if (!hooks.already_done || !hooks.already_done(i)) todo.push_back(i);
  if (todo.empty()) return out;
  // Start designs (OpenTURNS, serial): one per design dimension (with or without orientation).
  std::vector<std::vector<double>> designs(2);
  std::vector<std::size_t> which(set.size(), 0);
  for (std::size_t i : todo) {
    const std::size_t d = design_dim(model, shape, set.impacts[i], options);
    which[i] = d > box.size() ? 1 : 0;
    if (designs[which[i]].empty()) designs[which[i]] = start_design(box, model, d, options);
  }
  // Threads take interleaved groups of releases; within a group all searches run in lock-step
  // (fit/fibers.hpp). Results do not depend on the grouping.
  const int threads =
      std::max(1, std::min<int>(options.threads > 0 ? options.threads : omp_get_max_threads(),
                                static_cast<int>(todo.size())));
  std::string failure;
#pragma omp parallel for schedule(static, 1) num_threads(threads)
  for (int g = 0; g < threads; ++g) {
    try {
      detail::FiberPool pool(model, shape, pool_engine(options, 1));
      for (std::size_t k = static_cast<std::size_t>(g); k < todo.size();
           k += static_cast<std::size_t>(threads)) {
        const std::size_t i = todo[k];
        pool.spawn(
            [&, i] {
              out[i] = fit_release(pool, model, shape, set.impacts[i], options, designs[which[i]]);
            },
            [&, i] {
              if (hooks.on_done) {
#pragma omp critical(ricochet_fit_done)
                hooks.on_done(i, out[i]);
              }
            });
      }
      pool.run_all();
    } catch (const std::exception& e) {
#pragma omp critical(ricochet_fit_done)
      if (failure.empty()) failure = e.what();
    }
  }
  if (!failure.empty()) throw std::runtime_error("calibration failed: " + failure);
  return out;
}

ImpactSet select_shape(const ImpactSet& set, const Shape& shape) {
  ImpactSet out = set;
  out.impacts.clear();
  std::vector<std::string> present;
  for (const auto& im : set.impacts) {
    const std::string stem = std::filesystem::path(im.shape).stem().string();
    if (im.shape == shape.name || stem == shape.name) out.impacts.push_back(im);
    if (std::find(present.begin(), present.end(), im.shape) == present.end())
      present.push_back(im.shape);
  }
  if (out.empty()) {
    std::string list;
    for (const auto& s : present) list += (list.empty() ? "" : ", ") + s;
    throw InputError(set.source, 0, "shape",
                     "no release of shape '" + shape.name + "' (shapes in the data: " +
                         (list.empty() ? std::string("none") : list) + ")");
  }
  return out;
}

}  // namespace ricochet::fit
