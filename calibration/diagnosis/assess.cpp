#include "diagnosis/assess.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <map>
#include <stdexcept>

#include <omp.h>

#include "common/clock.hpp"
#include "common/progress.hpp"
#include "engine/engine.hpp"
#include "fit/collision_memo.hpp"

namespace ricochet::diagnosis {

namespace {

// The error options on `set`: the contact terms of the set's features (fit::with_contact_terms:
// switches and their constant denominators) unless use_features is off.
fit::ErrorOptions error_options_for(const ImpactSet& set, const AssessOptions& o) {
  if (o.use_features) return fit::with_contact_terms(o.fit.error, set);
  fit::ErrorOptions e = o.fit.error;
  e.penetration = e.contact_duration = false;
  return e;
}

}  // namespace

std::array<bool, kObservables> observables_of(const ImpactSet& set, const AssessOptions& o) {
  const fit::ErrorOptions e = error_options_for(set, o);
  return {true, true, true, e.penetration, e.contact_duration};
}

const char* error_scale_name(ErrorScale scale) {
  return scale == ErrorScale::kEq7 ? "eq7" : "set-mean";
}

AssessOptions resolve_scale(const ImpactSet& set, const AssessOptions& in) {
  AssessOptions o = in;
  if (o.unresolved_error || set.empty()) return o;  // resolved: resolving again changes nothing
  // Resolved once per set; a fold re-resolves on its training releases (resolve_scale_on).
  o.unresolved_error = in.fit.error;
  auto& e = o.fit.error;
  if (o.scale == ErrorScale::kSetMean) {
    const double n = static_cast<double>(set.size());
    Vel3 mean_v{};
    for (const auto& im : set.impacts)
      for (int k = 0; k < 3; ++k) mean_v[k] += std::fabs(im.vout[k]) / n;
    for (int k = 0; k < 3; ++k) e.floor[k] = std::max(e.floor[k], mean_v[k]);
  }
  // The contact terms and their constant denominators on this set, whatever the scale of the
  // velocity terms: the set's mean feature, at least its floor, decided in one place
  // (fit::with_contact_terms), the same in both modes.
  e = error_options_for(set, o);
  return o;
}

AssessOptions resolve_scale_on(const ImpactSet& subset, const AssessOptions& options) {
  AssessOptions o = options;
  if (o.unresolved_error) {
    o.fit.error = *o.unresolved_error;
    o.unresolved_error.reset();
  }
  return resolve_scale(subset, o);
}

fit::FitOptions fit_options_for(const ImpactSet& set, const AssessOptions& o) {
  fit::FitOptions f = o.fit;
  f.error = error_options_for(set, o);
  return f;
}

Model calibration_model_for(const Model& model, const ImpactSet& set, const AssessOptions& o) {
  return fit::calibration_model(model, fit_options_for(set, o).error);
}

Obs error_scale(const Impact& im, const AssessOptions& o) {
  const Vel3 d = fit::error_scale(im.vout, o.fit.error);
  const std::array<double, 2> c = fit::contact_error_scale(im, o.fit.error);
  return {d[0], d[1], d[2], c[0], c[1]};
}

Obs measured_of(const Impact& im) {
  return {im.vout[0], im.vout[1], im.vout[2], im.penetration.value_or(NAN),
          im.contact_duration.value_or(NAN)};
}

Obs ObsPrediction::quadrature_error() const {
  Obs e{};
  if (!has_halves) return e;
  for (int k = 0; k < kObservables; ++k)
    e[k] = std::max(std::fabs(half_value[0][k] - value[k]), std::fabs(half_value[1][k] - value[k]));
  return e;
}

ObsPrediction ObsPrediction::half(int h) const {
  ObsPrediction p = *this;
  if (!has_halves) return p;
  p.value = half_value[static_cast<std::size_t>(h)];
  p.spread = half_spread[static_cast<std::size_t>(h)];
  return p;
}

bool has_unknown_orientation(const Shape& shape, const ImpactSet& set) {
  if (shape.is_disc()) return false;
  return std::any_of(set.impacts.begin(), set.impacts.end(),
                     [](const Impact& im) { return !im.alpha_in.has_value(); });
}

int cold_starts(int starts, const AssessOptions& o, const Shape& shape, const ImpactSet& set) {
  return has_unknown_orientation(shape, set) ? std::max(starts, o.marginal_starts) : starts;
}

int full_set_starts(const AssessOptions& o, const fit::ErrorOptions& error, const Shape& shape,
                    const ImpactSet& set) {
  if (o.refine_start) return o.population_starts;
  return cold_starts(fit::uses_contact_terms(error)
                         ? std::max(o.population_starts, o.contact_population_starts)
                         : o.population_starts,
                     o, shape, set);
}

std::vector<ObsPrediction> to_observables(const std::vector<fit::Prediction>& predictions) {
  std::vector<ObsPrediction> out(predictions.size());
  for (std::size_t i = 0; i < predictions.size(); ++i) {
    const fit::Prediction& p = predictions[i];
    out[i].value = {p.vout[0], p.vout[1], p.vout[2], p.penetration_m, p.contact_duration_s};
    out[i].spread = {p.vout_std[0], p.vout_std[1], p.vout_std[2], 0.0, 0.0};
    out[i].status = p.status;
    out[i].has_halves = true;
    for (std::size_t h = 0; h < 2; ++h) {
      const Vel3& v = p.vout_half[h];
      const Vel3& sd = p.vout_std_half[h];
      out[i].half_value[h] = {v[0], v[1], v[2], p.penetration_half_m[h],
                              p.contact_duration_half_s[h]};
      out[i].half_spread[h] = {sd[0], sd[1], sd[2], 0.0, 0.0};
    }
  }
  return out;
}

std::vector<ObsPrediction> predict_observables(const Model& model, const Shape& shape,
                                               std::span<const double> params, const ImpactSet& set,
                                               const AssessOptions& o) {
  return to_observables(fit::predict(model, shape, params, set, fit_options_for(set, o)));
}

std::vector<ParameterProbe> probe_calibrated(const Model& model_in, const Shape& shape,
                                             const ImpactSet& set, const AssessOptions& o) {
  const Model model = calibration_model_for(model_in, set, o);
  std::vector<ParameterProbe> out;
  for (std::size_t j : model.calibrated_indices()) {
    std::vector<double> params = model.values();
    const double lo = model.lower(j), hi = model.upper(j), range = hi - lo;
    // A stiffness spans four decades: 2 % of its range would move it by 2e7 N/m, twice the
    // paper's kn; 2 % of its log range is a 20 % step, as the fit's own variable sees it.
    const bool log = fit::log_scaled(lo, hi);
    double step = log ? params[j] * (std::pow(hi / lo, 0.02) - 1.0) : 0.02 * range;
    if (params[j] + step > hi) step = log ? params[j] * (std::pow(hi / lo, -0.02) - 1.0) : -step;
    params[j] += step;
    out.push_back({j, step, range, predict_observables(model, shape, params, set, o)});
  }
  return out;
}

Obs error_terms(const Impact& im, const ObsPrediction& predicted,
                const std::array<bool, kObservables>& use, const AssessOptions& o) {
  const Obs d = error_scale(im, o);
  const Obs m = measured_of(im);
  Obs t{};
  for (int k = 0; k < kObservables; ++k) {
    if (!use[k]) continue;
    // Eq. 7 term (fit/error.hpp), expected over the orientation grid in marginal mode:
    // E[(v(alpha) - m)^2] = (mean - m)^2 + spread^2, the objective the fit module minimises.
    const double r = (predicted.value[k] - m[k]) / d[k];
    const double s = predicted.spread[k] / d[k];
    t[k] = r * r + s * s;
  }
  return t;
}

MeanSe mean_se(std::span<const double> x) {
  MeanSe m;
  m.n = x.size();
  if (x.empty()) return m;
  for (double v : x) m.mean += v / static_cast<double>(x.size());
  if (x.size() > 1) {
    double sq = 0;
    for (double v : x) sq += (v - m.mean) * (v - m.mean);
    m.se = std::sqrt(sq / static_cast<double>(x.size() - 1) / static_cast<double>(x.size()));
  }
  return m;
}

ErrorReport error_report(const ImpactSet& set, const std::vector<ObsPrediction>& predictions,
                         const std::array<bool, kObservables>& use, const AssessOptions& options) {
  const AssessOptions o = resolve_scale(set, options);
  if (predictions.size() != set.size())
    throw std::invalid_argument("error_report: one prediction per release expected");
  ErrorReport r;
  const double n = static_cast<double>(set.size());
  Obs sq{};
  std::array<double, 2> half_error{};
  for (std::size_t i = 0; i < set.size(); ++i) {
    const Impact& im = set.impacts[i];
    const Obs t = error_terms(im, predictions[i], use, o);
    for (int h = 0; h < 2; ++h)
      for (double x : error_terms(im, predictions[i].half(h), use, o))
        half_error[static_cast<std::size_t>(h)] += x / n;
    const Obs m = measured_of(im);
    Obs res{};
    double e = 0;
    for (int k = 0; k < kObservables; ++k) {
      res[k] = use[k] ? m[k] - predictions[i].value[k] : NAN;
      e += t[k];
      r.term_mean[k] += t[k] / n;
      if (use[k]) sq[k] += res[k] * res[k] / n;
    }
    r.per_release.push_back(e);
    r.terms.push_back(t);
    r.residual.push_back(res);
  }
  for (int k = 0; k < kObservables; ++k) r.rmse[k] = use[k] ? std::sqrt(sq[k]) : NAN;
  r.error = mean_se(r.per_release);
  r.quadrature_error =
      std::max(std::fabs(half_error[0] - r.error.mean), std::fabs(half_error[1] - r.error.mean));
  return r;
}

Model windowed(const Model& model, double window) {
  Model m = model;
  if (!(window < 1.0)) return m;
  for (std::size_t i : m.calibrated_indices()) {
    const double v = m.values()[i], lo = m.lower(i), hi = m.upper(i);
    // A parameter the fit searches in log(value) (fit::log_scaled: kn, 1e5-1e9 N/m) gets the
    // window in that variable, v / r to v r with r = (hi / lo)^window (x/ 4 for kn at 0.15): a
    // linear window of 0.15 x 1e9 N/m around 1e7 would be [1e5, 1.6e8], no window at all.
    if (fit::log_scaled(lo, hi) && v > 0) {
      const double r = std::pow(hi / lo, window);
      m.set_bounds(m.spec(i).name, std::max(lo, v / r), std::min(hi, v * r));
      continue;
    }
    const double half = window * (hi - lo);
    m.set_bounds(m.spec(i).name, std::max(lo, v - half), std::min(hi, v + half));
  }
  return m;
}

namespace {

// splitmix64 (Steele, Lea & Flood 2014): a seeded generator whose stream is the same on every
// platform, so a CV design depends only on its arguments.
std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

ImpactSet subset_of(const ImpactSet& set, const std::vector<std::size_t>& index) {
  ImpactSet out = set;
  out.impacts.clear();
  for (std::size_t i : index) out.impacts.push_back(set.impacts[i]);
  return out;
}

}  // namespace

CvDesign make_cv_design(std::size_t n, std::size_t folds, std::size_t repeats, std::uint64_t seed) {
  if (folds < 2 || folds > n)
    throw std::invalid_argument("cross-validation: folds must lie in [2, number of releases]");
  if (repeats < 1) throw std::invalid_argument("cross-validation: repeats must be >= 1");
  CvDesign cv;
  cv.n = n, cv.folds = folds, cv.repeats = repeats, cv.seed = seed;
  std::uint64_t state = seed * 0x2545F4914F6CDD1Dull + 0x1234567ull;
  for (std::size_t r = 0; r < repeats; ++r) {
    std::vector<std::size_t> perm(n);
    for (std::size_t i = 0; i < n; ++i) perm[i] = i;
    for (std::size_t i = n - 1; i > 0; --i)  // Fisher-Yates
      std::swap(perm[i], perm[splitmix64(state) % (i + 1)]);
    for (std::size_t f = 0; f < folds; ++f) {
      std::vector<std::size_t> test, train;
      for (std::size_t p = 0; p < n; ++p) (p % folds == f ? test : train).push_back(perm[p]);
      std::sort(test.begin(), test.end());
      std::sort(train.begin(), train.end());
      cv.test.push_back(std::move(test));
      cv.train.push_back(std::move(train));
    }
  }
  return cv;
}

std::vector<double> carry_values(const Model& to, const std::vector<std::string>& from_names,
                                 const std::vector<double>& from_values) {
  std::vector<double> v = to.values();
  for (std::size_t k = 0; k < from_names.size() && k < from_values.size(); ++k)
    for (std::size_t i = 0; i < to.parameter_count(); ++i)
      if (to.spec(i).name == from_names[k]) v[i] = from_values[k];
  return v;
}

fit::PopulationFit refine_warm(const Model& start, const Shape& shape, const ImpactSet& set,
                               const fit::FitOptions& options) {
  Model held = start;
  bool any = false;
  for (std::size_t i = 0; i < start.parameter_count(); ++i) {
    if (start.spec(i).identified_by != IdentifiedBy::kContactFeatures || !held.calibrated(i))
      continue;
    held.set_bounds(start.spec(i).name, held.values()[i], held.values()[i]);
    any = true;
  }
  if (!any) return fit::calibrate_population(start, shape, set, options);
  const fit::PopulationFit first = fit::calibrate_population(held, shape, set, options);
  Model released = start;
  released.set_values(first.params);
  fit::PopulationFit second = fit::calibrate_population(released, shape, set, options);
  return second.error <= first.error ? second : first;
}

Model nominal_start(const Model& model) {
  Model m = model;
  std::vector<double> v = m.values();
  for (std::size_t i : m.calibrated_indices())
    v[i] = std::clamp(m.spec(i).nominal, m.lower(i), m.upper(i));
  m.set_values(v);
  return m;
}

namespace {

// The full-set calibration (the in-sample fit; never a start of a split's fit).
fit::PopulationFit full_set_fit(const Model& model, const Shape& shape, const ImpactSet& set,
                                const AssessOptions& o, const fit::FitOptions& fo) {
  fit::PopulationFit best = fit::calibrate_population(model, shape, set, fo);
  if (o.refine_start) {
    // A warm model (a calibrated one plus an effect at its neutral value) is also refined
    // locally from its own values: the global search's local runs start from the best design
    // points and can leave the calibrated basin for a worse one.
    fit::FitOptions fl = fo;
    fl.starts = 1;
    fl.design_points = o.fold_warm_design_points;
    const fit::PopulationFit local = refine_warm(windowed(model, 0.15), shape, set, fl);
    if (local.error < best.error) best = local;
  }
  return best;
}

// One split's fit on its training releases, warm-started from the base model's optimum on the
// same split: local refinements from the best points of a line through the added parameters'
// range (the warm value first), scored on the training releases by one prediction batch each
// (AssessOptions::fold_warm_*).
fit::PopulationFit warm_split_fit(const Model& mj, const Shape& shape, const ImpactSet& train,
                                  fit::FitOptions fj, const AssessOptions& o,
                                  const Assessment& warm, std::size_t j) {
  fj.starts = o.fold_warm_starts;
  fj.design_points = o.fold_warm_design_points;
  const std::vector<double> from = carry_values(mj, warm.names, warm.fold_params[j]);
  // Calibrated parameters the warm assessment's model does not have (the added effect's).
  std::vector<std::size_t> added;
  for (std::size_t i : mj.calibrated_indices())
    if (std::find(warm.names.begin(), warm.names.end(), mj.spec(i).name) == warm.names.end())
      added.push_back(i);
  std::vector<std::pair<double, std::vector<double>>> line;
  for (double frac : o.fold_added_line) {
    std::vector<double> v = from;
    for (std::size_t i : added)
      if (frac >= 0) v[i] = mj.lower(i) + frac * (mj.upper(i) - mj.lower(i));
    const auto pr = fit::predict(mj, shape, v, train, fj);
    double e = 0;
    for (double x : fit::prediction_errors(train, pr, fj.error)) e += x;
    for (const auto& q : pr) e += q.status == CollisionStatus::kOk ? 0.0 : fit::kFailedRebound;
    if (fj.extra_objective) e += fj.extra_objective(mj, v, train);  // as the fit minimises
    line.emplace_back(e, std::move(v));
  }
  std::stable_sort(line.begin(), line.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  fit::PopulationFit pf;
  for (std::size_t t = 0; t < line.size() && t < o.fold_refinements; ++t) {
    Model start = mj;
    start.set_values(line[t].second);
    fit::PopulationFit f = refine_warm(start, shape, train, fj);
    if (pf.params.empty() || f.error < pf.error) pf = std::move(f);
  }
  return pf;
}

/// What every split's fit gives: its test releases' predictions and the options (scale) they
/// are judged with.
struct SplitOutcome {
  std::vector<ObsPrediction> predictions;
  AssessOptions options;
};

// Fits every split of a.cv on its training releases alone (file comment) and predicts its test
// releases; fills a.fold_params (and a.fold_models with a split model). Each split starts from
// values no data chose (issue 31, 5a): the model's own values may be a fit to this very set (a
// ladder's next round, `diagnose --model` with a model written from it), and a fold fit started
// there would carry its held-out releases in through the start point.
std::vector<SplitOutcome> fit_splits(Assessment& a, const Model& model, const Shape& shape,
                                     const ImpactSet& set, const AssessOptions& options,
                                     const AssessOptions& o, const Assessment* warm,
                                     const SplitModel& split_model) {
  const std::size_t splits = a.cv.splits();
  // Split models are made here, one after the other, so that a maker that runs engines or
  // reads files need not be thread-safe.
  if (split_model)
    for (std::size_t j = 0; j < splits; ++j)
      a.fold_models.push_back(calibration_model_for(split_model(a.cv.train[j]), set, o));
  a.fold_params.resize(splits);
  std::vector<SplitOutcome> out(splits);
  std::vector<std::exception_ptr> failure(splits);
  const auto fit_split = [&](std::size_t j) {
    const ImpactSet train = subset_of(set, a.cv.train[j]);
    const ImpactSet test = subset_of(set, a.cv.test[j]);
    const Model& mj = a.fold_models.empty() ? model : a.fold_models[j];
    out[j].options = resolve_scale_on(train, options);
    fit::FitOptions fj = fit_options_for(train, out[j].options);
    fj.intervals = false;
    fit::PopulationFit pf;
    if (warm) {
      pf = warm_split_fit(mj, shape, train, fj, o, *warm, j);
    } else {
      fj.starts = cold_starts(o.fold_starts, o, shape, train);
      pf = fit::calibrate_population(nominal_start(mj), shape, train, fj);
    }
    a.fold_params[j] = pf.params;
    out[j].predictions = predict_observables(mj, shape, pf.params, test, out[j].options);
    if (o.progress) o.progress->advance();
  };
  // The splits' fits are independent: they run in parallel (one split per thread; the engine
  // then runs each batch on its thread, engine.cpp), and the caller sums them in split order,
  // so the result does not depend on the thread count. A cylinder set of 28 releases is one
  // engine block: without this the leak-free diagnosis ran on one core.
  const int threads = static_cast<int>(std::min<std::size_t>(
      splits, static_cast<std::size_t>(o.fit.threads > 0 ? o.fit.threads : omp_get_max_threads())));
#pragma omp parallel for schedule(dynamic, 1) \
    num_threads(threads) if (threads > 1 && !omp_in_parallel())
  for (std::size_t j = 0; j < splits; ++j) {
    try {
      fit_split(j);
    } catch (...) {
      failure[j] = std::current_exception();
    }
  }
  for (std::size_t j = 0; j < splits; ++j)
    if (failure[j]) std::rethrow_exception(failure[j]);
  return out;
}

// Each release's held-out prediction, terms and error: the mean over the repeats of the splits
// that held it out; a.split_error and a.repeat_error on the way.
void pool_heldout(Assessment& a, const ImpactSet& set, const std::vector<SplitOutcome>& splits) {
  const std::size_t n = set.size(), R = a.cv.repeats;
  a.split_error.resize(splits.size());
  a.repeat_error.assign(R, std::vector<double>(n, NAN));
  std::vector<Obs> pred_sum(n, Obs{}), spread_sum(n, Obs{}), term_sum(n, Obs{}), inv_sum(n, Obs{});
  std::vector<int> worst(n, 0);
  std::array<double, 2> half_sum{};  // summed errors with the half orientation rules
  // The held-out predictions' half-rule values and spreads, pooled like the predictions.
  std::vector<std::array<Obs, 2>> half_value_sum(n), half_spread_sum(n);
  std::vector<char> halves(n, 1);
  for (std::size_t j = 0; j < splits.size(); ++j) {
    const std::vector<std::size_t>& test = a.cv.test[j];
    const AssessOptions& oj = splits[j].options;
    const std::vector<ObsPrediction>& pred = splits[j].predictions;
    const std::size_t r = j / a.cv.folds;
    double sum = 0;
    for (std::size_t t = 0; t < test.size(); ++t) {
      const std::size_t i = test[t];
      const Obs terms = error_terms(set.impacts[i], pred[t], a.use, oj);
      const Obs d = error_scale(set.impacts[i], oj);
      double e = 0;
      for (int k = 0; k < kObservables; ++k) {
        e += terms[k];
        term_sum[i][k] += terms[k];
        pred_sum[i][k] += pred[t].value[k];
        spread_sum[i][k] += pred[t].spread[k];
        inv_sum[i][k] += a.use[k] ? 1.0 / (d[k] * d[k]) : 0.0;
      }
      worst[i] = std::max(worst[i], static_cast<int>(pred[t].status));
      for (std::size_t hh = 0; hh < 2; ++hh) {
        const ObsPrediction q = pred[t].half(static_cast<int>(hh));
        for (double x : error_terms(set.impacts[i], q, a.use, oj)) half_sum[hh] += x;
        for (int k = 0; k < kObservables; ++k) {
          half_value_sum[i][hh][k] += q.value[k];
          half_spread_sum[i][hh][k] += q.spread[k];
        }
      }
      halves[i] = halves[i] && pred[t].has_halves;
      a.repeat_error[r][i] = e;
      sum += e;
    }
    a.split_error[j] = sum / static_cast<double>(test.size());
  }
  const double rr = static_cast<double>(R);
  a.heldout_predictions.resize(n);
  a.heldout_inv_scale2.resize(n);
  ErrorReport& h = a.heldout;
  Obs sq{};
  for (std::size_t i = 0; i < n; ++i) {
    ObsPrediction& p = a.heldout_predictions[i];
    Obs terms{}, res{};
    double e = 0;
    const Obs m = measured_of(set.impacts[i]);
    for (int k = 0; k < kObservables; ++k) {
      p.value[k] = pred_sum[i][k] / rr;
      p.spread[k] = spread_sum[i][k] / rr;
      terms[k] = term_sum[i][k] / rr;
      a.heldout_inv_scale2[i][k] = inv_sum[i][k] / rr;
      e += terms[k];
      res[k] = a.use[k] ? m[k] - p.value[k] : NAN;
      h.term_mean[k] += terms[k] / static_cast<double>(n);
      if (a.use[k]) sq[k] += res[k] * res[k] / static_cast<double>(n);
    }
    p.status = static_cast<CollisionStatus>(worst[i]);
    p.has_halves = halves[i] != 0;
    for (std::size_t hh = 0; hh < 2; ++hh)
      for (int k = 0; k < kObservables; ++k) {
        p.half_value[hh][k] = half_value_sum[i][hh][k] / rr;
        p.half_spread[hh][k] = half_spread_sum[i][hh][k] / rr;
      }
    h.per_release.push_back(e);
    h.terms.push_back(terms);
    h.residual.push_back(res);
  }
  for (int k = 0; k < kObservables; ++k) h.rmse[k] = a.use[k] ? std::sqrt(sq[k]) : NAN;
  h.error = mean_se(h.per_release);
  const double scale = 1.0 / (rr * static_cast<double>(n));
  h.quadrature_error = std::max(std::fabs(half_sum[0] * scale - h.error.mean),
                                std::fabs(half_sum[1] * scale - h.error.mean));
}

// The fold optima are candidates for the full-set optimum too. On a rough objective (lab
// triangles: rebound statuses and orientation cells switch as the parameters move) fold fits
// have found parameters fitting the WHOLE set better than the full-set multi-start (0.827
// against 0.935): it had stopped on a kink. The fold optima are ranked by the full-set objective
// (expected error over orientations, as the fit module minimises, plus the failed-rebound
// penalty); the two best that beat the full-set optimum are refined locally on the full set.
// This touches the full-set (in-sample) fit only: the held-out predictions never depend on it.
// Split models' optima are not `model`'s parameters (a fixed coefficient differs): none.
void polish_with_fold_optima(Assessment& a, const Model& model, const Shape& shape,
                             const ImpactSet& set, const AssessOptions& o,
                             const fit::FitOptions& fo) {
  if (!a.fold_models.empty()) return;
  std::vector<std::pair<double, std::size_t>> better;
  for (std::size_t k = 0; k < a.fold_params.size(); ++k) {
    const auto pr = fit::predict(model, shape, a.fold_params[k], set, fo);
    const ErrorReport r = error_report(set, to_observables(pr), a.use, o);
    double e = r.error.mean * static_cast<double>(set.size());
    for (const auto& q : pr) e += q.status == CollisionStatus::kOk ? 0.0 : fit::kFailedRebound;
    if (fo.extra_objective) e += fo.extra_objective(model, a.fold_params[k], set);
    if (e < a.population.error) better.emplace_back(e, k);
  }
  std::sort(better.begin(), better.end());
  for (std::size_t t = 0; t < better.size() && t < 2; ++t) {
    Model from = model;
    from.set_values(a.fold_params[better[t].second]);
    fit::FitOptions fl = fo;
    fl.starts = 1;
    fl.design_points = -1;
    fit::PopulationFit polished = fit::calibrate_population(windowed(from, 0.15), shape, set, fl);
    if (polished.error < a.population.error) a.population = std::move(polished);
  }
}

Assessment assess_splits(const Model& model_in, const Shape& shape, const ImpactSet& set,
                         const AssessOptions& options, const Assessment* warm,
                         const SplitModel& split_model) {
  require_valid(options.problems(), "diagnosis::assess");
  const AssessOptions o = resolve_scale(set, options);
  // The parameters every fit below calibrates (the fit module decides the same way).
  const Model model = calibration_model_for(model_in, set, o);
  const auto t0 = std::chrono::steady_clock::now();
  const std::uint64_t c0 = collisions_simulated();
  if (set.size() < 2) throw std::invalid_argument("assess: at least two releases are needed");
  const std::size_t n = set.size();
  Assessment a;
  a.effects = model.effect_names();
  a.names = model.parameter_names();
  for (std::size_t i : model.calibrated_indices()) a.calibrated.emplace_back(model.spec(i).name);
  a.use = observables_of(set, o);
  // The full-set fit and the cold fold fits share their start design's collisions
  // (fit/collision_memo.hpp); the full-set fit runs first and stores them.
  AssessOptions shared = options;
  if (!shared.fit.memo)
    shared.fit.memo = std::make_shared<fit::CollisionMemo>(
        fit::collision_memo_scope(model, shape, shared.fit.engine));
  fit::FitOptions fo = fit_options_for(set, o);
  fo.memo = shared.fit.memo;
  fo.intervals = false;
  fo.starts = full_set_starts(o, fo.error, shape, set);
  a.population = full_set_fit(model, shape, set, o, fo);
  if (o.progress) o.progress->advance();
  if (warm) {
    if (warm->cv.n != n)
      throw std::invalid_argument("assess: the warm assessment is of another set");
    a.cv = warm->cv;
  } else {
    a.cv = make_cv_design(n, o.folds_for(n), o.repeats, o.fit.seed);
  }
  a.folds = a.cv.folds;
  pool_heldout(a, set, fit_splits(a, model, shape, set, shared, o, warm, split_model));
  polish_with_fold_optima(a, model, shape, set, o, fo);
  a.insample_predictions = to_observables(a.population.predictions);
  a.insample = error_report(set, a.insample_predictions, a.use, o);
  a.seconds = seconds_since(t0);
  a.collisions = collisions_simulated() - c0;
  return a;
}

}  // namespace

Assessment assess(const Model& model, const Shape& shape, const ImpactSet& set,
                  const AssessOptions& options, const Assessment* warm) {
  return assess_splits(model, shape, set, options, warm, {});
}

Assessment assess(const Model& model, const Shape& shape, const ImpactSet& set,
                  const AssessOptions& options, const SplitModel& split_model) {
  return assess_splits(model, shape, set, options, nullptr, split_model);
}

std::vector<double> floor_on_heldout_scale(const Assessment& a, const NoiseFloor& floor) {
  const std::size_t n = a.heldout.per_release.size();
  if (floor.variance.size() != n || a.heldout_inv_scale2.size() != n) return floor.per_release;
  std::vector<double> f(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < kObservables; ++k)
      if (a.use[k]) f[i] += floor.variance[i][k] * a.heldout_inv_scale2[i][k];
  return f;
}

Adequacy adequacy(const Assessment& a, const NoiseFloor& floor) {
  Adequacy q;
  const double n_train = a.cv.train_size();
  const double p = static_cast<double>(a.calibrated.size());
  const double inflate = 1.0 + p / std::max(1.0, n_train);
  const std::vector<double> f = floor_on_heldout_scale(a, floor);
  std::vector<double> x(a.heldout.per_release.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = a.heldout.per_release[i] - f[i] * inflate;
  const MeanSe m = mean_se(x);
  const double floor_mean = mean_se(f).mean;
  q.excess = m.mean;
  q.excess_se = m.se;
  q.threshold = floor_mean * inflate + 2.0 * m.se;
  q.ratio = floor_mean > 0 ? a.heldout.error.mean / floor_mean : INFINITY;
  q.adequate = m.mean <= 2.0 * m.se;
  return q;
}

nlohmann::json to_json(const MeanSe& m) {
  return {{"mean", m.mean}, {"se", m.se}, {"n", m.n}};
}

nlohmann::json to_json(const Obs& o, const std::array<bool, kObservables>& use) {
  nlohmann::json j = nlohmann::json::object();
  for (int k = 0; k < kObservables; ++k)
    if (use[k]) j[kObservableNames[k]] = o[k];
  return j;
}

nlohmann::json to_json(const NoiseFloor& f, const std::array<bool, kObservables>& use) {
  nlohmann::json j = {{"value", f.value.mean},
                      {"se", f.value.se},
                      {"source", f.source},
                      {"description", f.description},
                      {"per_component", to_json(f.term_mean, use)},
                      {"sigma", to_json(f.sigma_mean, use)},
                      {"nearest_neighbour", f.nearest_neighbour},
                      {"replicate_groups", f.replicate_groups}};
  // The orientation term only where there is one (a set of known orientation reads as before).
  if (f.orientation_share > 0) j["orientation_term"] = f.orientation_share;
  return j;
}

}  // namespace ricochet::diagnosis
