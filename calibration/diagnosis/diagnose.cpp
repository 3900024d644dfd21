#include "diagnosis/diagnose.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>

#include "common/error.hpp"
#include "common/progress.hpp"

namespace ricochet::diagnosis {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

const EffectRegistry& registry_of(const DiagnoseOptions& o) {
  return o.registry ? *o.registry : EffectRegistry::global();
}

// Regimes: thirds of the releases by |V_in| (at least 2 releases each).
std::vector<Regime> regimes_of(const ImpactSet& set, const Assessment& a, const NoiseFloor& f) {
  const std::size_t n = set.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto speed = [&](std::size_t i) {
    return std::hypot(set.impacts[i].vin[0], set.impacts[i].vin[1]);
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return speed(x) < speed(y); });
  const std::size_t parts = n >= 6 ? 3 : 1;
  std::vector<Regime> out;
  const char* names[3] = {"slow third", "middle third", "fast third"};
  for (std::size_t p = 0; p < parts; ++p) {
    Regime r;
    const std::size_t lo = p * n / parts, hi = (p + 1) * n / parts;
    r.releases.assign(order.begin() + lo, order.begin() + hi);
    r.name = parts == 1 ? std::string("all releases")
                        : fmt::format("{}: |V_in| {:.2f}-{:.2f} m/s", names[p], speed(order[lo]),
                                      speed(order[hi - 1]));
    std::vector<double> e, fl;
    for (std::size_t i : r.releases) {
      e.push_back(a.heldout.per_release[i]);
      fl.push_back(f.per_release[i]);
    }
    r.heldout = mean_se(e);
    r.floor = mean_se(fl);
    out.push_back(std::move(r));
  }
  return out;
}

// What each built-in effect stands for and which trends the shared notes
// (physics-candidates.md) give as its signature.
struct Hint {
  std::string meaning;
  std::vector<std::pair<std::string, std::string>> trends;  // (quantity, feature)
};
const std::map<std::string, Hint>& hints() {
  static const std::map<std::string, Hint> h = {
      {"rate_restitution",
       {"speed-dependent restitution",
        {{"residual vy", "abs_vin_y"}, {"param en2", "abs_vin_y"}, {"param en2", "speed_in"}}}},
      {"inertial_drag",
       {"inertial drag of the sand (a force growing with the speed squared)",
        {{"residual vy", "speed_in"},
         {"residual vx", "speed_in"},
         {"residual penetration", "speed_in"},
         {"param en2", "speed_in"}}}},
      {"ploughing",
       {"passive earth pressure (ploughing) growing with the depth squared",
        {{"residual vx", "penetration"},
         {"param mu", "penetration"},
         {"param muR", "penetration"}}}},
      {"depth_friction",
       {"friction hardening with penetration depth",
        {{"param mu", "penetration"},
         {"residual vx", "penetration"},
         {"residual w", "penetration"}}}},
      {"hertz_stiffness",
       {"a normal stiffness growing with penetration (Hertz-like bearing)",
        {{"residual contact_duration", "speed_in"},
         {"residual penetration", "speed_in"},
         {"residual contact_duration", "abs_vin_y"}}}},
  };
  return h;
}

// Mean residual of an observable with its t statistic (a bias, e.g. contact always too long).
std::string bias_text(const ErrorReport& r, int k) {
  std::vector<double> x;
  for (const auto& res : r.residual) x.push_back(res[k]);
  const MeanSe m = mean_se(x);
  if (!(m.se > 0)) return {};
  const double t = m.mean / m.se;
  if (std::fabs(t) < 3) return {};
  const double scale = k == kObsPenetration ? 1e3 : k == kObsDuration ? 1e3 : 1.0;
  const char* unit = k == kObsPenetration ? "mm" : k == kObsDuration ? "ms" : kObservableUnits[k];
  return fmt::format("measured {} is {} than predicted by {:.3g} {} on average (t = {:.1f})",
                     kObservableLabels[k], m.mean > 0 ? "larger" : "smaller",
                     std::fabs(m.mean) * scale, unit, t);
}

// The base model's directions: d(prediction)/d(parameter) / d, stacked over releases and used
// observables, one column per calibrated base parameter.
struct Directions {
  Eigen::MatrixXd X;                              // base parameter directions
  Eigen::VectorXd z;                              // scaled in-sample residuals, projected
  Eigen::MatrixXd proj;                           // I - X (X^T X)^-1 X^T
  std::vector<std::pair<std::size_t, int>> rows;  // (release, observable)
};

std::vector<std::pair<std::size_t, int>> rows_of(std::size_t n,
                                                 const std::array<bool, kObservables>& use) {
  std::vector<std::pair<std::size_t, int>> rows;
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < kObservables; ++k)
      if (use[k]) rows.emplace_back(i, k);
  return rows;
}

Eigen::VectorXd scaled_change(const std::vector<ObsPrediction>& a,
                              const std::vector<ObsPrediction>& b, const ImpactSet& set,
                              const std::vector<std::pair<std::size_t, int>>& rows, double step,
                              const AssessOptions& o) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto [i, k] = rows[r];
    const double d = error_scale(set.impacts[i], o)[k];
    const double x = (a[i].value[k] - b[i].value[k]) / step / d;
    v[static_cast<Eigen::Index>(r)] = std::isfinite(x) ? x : 0.0;
  }
  return v;
}

Directions base_directions(const Model& warm, const Shape& shape, const ImpactSet& set,
                           const Assessment& base, const AssessOptions& o) {
  Directions d;
  d.rows = rows_of(set.size(), base.use);
  const auto& p0 = base.insample_predictions;
  const std::vector<std::size_t> cal = warm.calibrated_indices();
  d.X.resize(static_cast<Eigen::Index>(d.rows.size()), static_cast<Eigen::Index>(cal.size()));
  for (std::size_t c = 0; c < cal.size(); ++c) {
    const std::size_t j = cal[c];
    std::vector<double> params = warm.values();
    double step = 0.02 * (warm.upper(j) - warm.lower(j));
    if (params[j] + step > warm.upper(j)) step = -step;
    params[j] += step;
    const auto p = predict_observables(warm, shape, params, set, o);
    d.X.col(static_cast<Eigen::Index>(c)) = scaled_change(p, p0, set, d.rows, step, o);
  }
  const Eigen::Index N = d.X.rows();
  d.proj = Eigen::MatrixXd::Identity(N, N);
  if (d.X.cols() > 0) {
    // Pseudo-inverse through a complete orthogonal decomposition: collinear directions (a
    // parameter that does nothing at the optimum) are harmless.
    const Eigen::MatrixXd pinv = d.X.completeOrthogonalDecomposition().pseudoInverse();
    d.proj -= d.X * pinv;
  }
  Eigen::VectorXd z(N);
  for (std::size_t r = 0; r < d.rows.size(); ++r) {
    const auto [i, k] = d.rows[r];
    const double s = error_scale(set.impacts[i], o)[k];
    z[static_cast<Eigen::Index>(r)] = base.insample.residual[i][k] / s;
  }
  d.z = d.proj * z;
  return d;
}

// The score-test correlation of a candidate (file comment of diagnose.hpp): the largest over its
// calibrated parameters.
double signature_r(const Directions& dirs, const Model& cand, const Shape& shape,
                   const ImpactSet& set, const std::vector<std::size_t>& added,
                   const DiagnoseOptions& o) {
  if (dirs.z.norm() == 0) return NAN;
  const auto p0 = predict_observables(cand, shape, cand.values(), set, o.assess);
  double best = NAN;
  for (std::size_t j : added) {
    std::vector<double> params = cand.values();
    const double toward = params[j] <= cand.lower(j)   ? cand.upper(j)
                          : params[j] >= cand.upper(j) ? cand.lower(j)
                                                       : cand.upper(j);
    const double step = o.probe_fraction * (toward - params[j]);
    if (step == 0) continue;
    params[j] += step;
    const auto p = predict_observables(cand, shape, params, set, o.assess);
    const Eigen::VectorXd s = dirs.proj * scaled_change(p, p0, set, dirs.rows, step, o.assess);
    if (s.norm() == 0) continue;
    // Sign convention: positive when increasing the parameter from neutral moves the
    // predictions towards the measurements.
    const double r = dirs.z.dot(s) / (dirs.z.norm() * s.norm()) * (step > 0 ? 1.0 : -1.0);
    if (!(std::fabs(r) <= std::fabs(best))) best = r;
  }
  return best;
}

std::string evidence_of(const Candidate& c, const Baseline& b, const Assessment& base) {
  std::vector<std::string> parts;
  parts.push_back(fmt::format(
      "held-out error {:.4g} vs {:.4g} for the base model (drop {:.3g} +- {:.2g}, {:.1f} SE; "
      "penalty for {} added parameter{} {:.2g}; noise floor {:.4g})",
      c.heldout_error, base.heldout.error.mean, c.error_drop, c.drop_se,
      c.drop_se > 0 ? c.error_drop / c.drop_se : 0.0, c.added_parameters.size(),
      c.added_parameters.size() == 1 ? "" : "s", c.penalty, b.floor.value.mean));
  // The observable whose error falls most.
  int best_k = -1;
  double best_drop = 0;
  for (int k = 0; k < kObservables; ++k) {
    if (!base.use[k]) continue;
    const double d = base.heldout.term_mean[k] - c.assessment.heldout.term_mean[k];
    if (d > best_drop) best_drop = d, best_k = k;
  }
  if (best_k >= 0)
    parts.push_back(fmt::format("the {} error falls most ({:.3g} -> {:.3g})",
                                kObservableLabels[best_k], base.heldout.term_mean[best_k],
                                c.assessment.heldout.term_mean[best_k]));
  if (std::isfinite(c.signature_r))
    parts.push_back(fmt::format("its signature {} the base model's residuals (r = {:.2f})",
                                c.signature_r > 0.3 ? "matches"
                                : c.signature_r > 0 ? "weakly matches"
                                                    : "opposes",
                                c.signature_r));
  for (std::size_t i = 0; i < c.added_parameters.size(); ++i)
    parts.push_back(
        fmt::format("calibrated {} = {:.4g}", c.added_parameters[i], c.added_values[i]));
  const auto it = hints().find(c.effect);
  if (it != hints().end()) {
    for (const auto& [q, f] : it->second.trends) {
      const std::vector<Trend>& pool =
          q.rfind("param", 0) == 0 ? b.parameter_trends : b.residual_trends;
      if (const Trend* t = find_trend(pool, q, f); t && t->significant)
        parts.push_back(describe(*t));
    }
    if (c.effect == "hertz_stiffness")
      for (int k : {kObsPenetration, kObsDuration})
        if (base.use[k])
          if (std::string s = bias_text(base.heldout, k); !s.empty()) parts.push_back(s);
  }
  std::string text;
  for (const auto& p : parts) text += (text.empty() ? "" : "; ") + p;
  text += c.supported ? ": consistent with " + c.meaning
                      : ": not supported (the drop does not exceed its uncertainty and penalty)";
  return text;
}

std::vector<std::string> unexplained_after(const Assessment& a, const NoiseFloor& floor,
                                           const Adequacy& q, const std::vector<Feature>& features,
                                           const TrendOptions& to, const std::string& who) {
  std::vector<std::string> out;
  out.push_back(fmt::format(
      "{}: held-out error {:.4g} = {:.2f} x the noise floor {:.4g} ({})", who, a.heldout.error.mean,
      q.ratio, floor.value.mean,
      q.adequate ? "within the floor" : fmt::format("above the threshold {:.4g}", q.threshold)));
  // Per-observable excess over the floor.
  for (int k = 0; k < kObservables; ++k) {
    if (!a.use[k]) continue;
    const double ratio =
        floor.term_mean[k] > 0 ? a.heldout.term_mean[k] / floor.term_mean[k] : INFINITY;
    if (ratio > 2)
      out.push_back(fmt::format("{} error {:.3g} is {:.1f} x its noise floor {:.3g}",
                                kObservableLabels[k], a.heldout.term_mean[k], ratio,
                                floor.term_mean[k]));
  }
  std::vector<Trend> trends = residual_trends(a.heldout, a.use, features, to);
  std::stable_sort(trends.begin(), trends.end(),
                   [](const Trend& x, const Trend& y) { return x.p < y.p; });
  // One line per residual: its strongest trend, then the other features it also trends with.
  // In a designed set the features move together (speeds campaign: |V_in|, V_in^x, V_in^y and
  // omega_in all scale at once) and one line per pair buried the conclusions in 28 near-copies.
  std::vector<std::string> quantities;
  for (const auto& t : trends)
    if (t.significant &&
        std::find(quantities.begin(), quantities.end(), t.quantity) == quantities.end())
      quantities.push_back(t.quantity);
  for (const auto& q : quantities) {
    std::string line, also;
    for (const auto& t : trends) {
      if (!t.significant || t.quantity != q) continue;
      if (line.empty())
        line = describe(t);
      else
        also += (also.empty() ? "" : ", ") + t.feature_label;
    }
    if (!also.empty()) line += "; also with " + also + " (features correlated in this set)";
    out.push_back(line);
  }
  for (int k : {kObsPenetration, kObsDuration})
    if (a.use[k])
      if (std::string s = bias_text(a.heldout, k); !s.empty()) out.push_back(s);
  if (out.size() == 1 && !q.adequate)
    out.push_back(
        "no residual trend with any impact feature: unstructured scatter (e.g. "
        "release-to-release variability of the ground, or a noise floor set too low)");
  return out;
}

}  // namespace

Model with_values(const Model& model, const std::vector<double>& values) {
  Model m = model;
  m.set_values(values);
  return m;
}

Baseline compare(const Model& model, const Shape& shape, const ImpactSet& set,
                 const DiagnoseOptions& options) {
  DiagnoseOptions o = options;
  o.assess = resolve_scale(set, options.assess);
  const auto t0 = std::chrono::steady_clock::now();
  Baseline b;
  b.base = assess(model, shape, set, o.assess);
  const auto& ef = o.assess.fit.error;
  b.error_floors = {ef.floor[0], ef.floor[1], ef.floor[2], ef.penetration_floor_m,
                    ef.contact_duration_floor_s};
  const Model warm = with_values(model, b.base.population.params);
  b.floor = noise_floor(warm, shape, b.base.population.params, set, b.base.use, o.assess);
  b.adequacy = adequacy(b.base, b.floor);
  std::vector<double> alpha;
  if (o.assess.release_fits) {
    fit::FitOptions fo = fit_options_for(set, o.assess);
    fo.intervals = o.assess.release_intervals;
    b.release_fits = fit::calibrate_releases(warm, shape, set, fo);
    for (const auto& f : b.release_fits) alpha.push_back(f.alpha_rad);
  }
  b.features = impact_features(set, b.base.insample_predictions, alpha);
  b.residual_trends = residual_trends(b.base.heldout, b.base.use, b.features, o.trends);
  b.parameter_trends = parameter_trends(b.release_fits, b.features, o.trends);
  b.regimes = regimes_of(set, b.base, b.floor);
  for (int k = 0; k < kObservables; ++k) {
    if (!b.base.use[k]) continue;
    std::vector<double> meas, pred;
    for (std::size_t i = 0; i < set.size(); ++i) {
      pred.push_back(b.base.heldout_predictions[i].value[k]);
      meas.push_back(pred.back() + b.base.heldout.residual[i][k]);
    }
    b.ks[k] = stats::ks_two_sample(meas, pred);
  }
  b.seconds = seconds_since(t0);
  return b;
}

Diagnosis diagnose(const Model& model, const Shape& shape, const ImpactSet& set,
                   const DiagnoseOptions& o) {
  return diagnose(compare(model, shape, set, o), model, shape, set, o);
}

Diagnosis diagnose(Baseline baseline, const Model& model, const Shape& shape, const ImpactSet& set,
                   const DiagnoseOptions& options) {
  DiagnoseOptions o = options;
  o.assess = resolve_scale(set, options.assess);
  const auto t0 = std::chrono::steady_clock::now();
  Diagnosis d;
  d.baseline = std::move(baseline);
  const Baseline& b = d.baseline;
  const Assessment& base = b.base;
  const EffectRegistry& registry = registry_of(o);
  const Model warm = with_values(model, base.population.params);

  std::vector<std::string> names = o.candidates;
  if (names.empty())
    for (const auto& n : registry.names())
      if (!model.has_effect(n)) names.push_back(n);

  const Directions dirs = base_directions(warm, shape, set, base, o.assess);
  const double n = static_cast<double>(set.size());
  const double n_train = n * static_cast<double>(base.folds - 1) / static_cast<double>(base.folds);

  Progress progress("diagnose", names.size(), o.progress);
  // Candidates are independent: they run in parallel, each calibration on one thread (the fit
  // module is deterministic, so the results do not depend on the thread count).
  const int threads = std::max(
      1, std::min<int>(o.assess.fit.threads > 0 ? o.assess.fit.threads : omp_get_max_threads(),
                       static_cast<int>(names.size())));
  std::vector<Candidate> tried(names.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string& name = names[k];
    progress.status(name);
    Candidate c;
    c.effect = name;
    const auto hint = hints().find(name);
    try {
      const Effect& effect = registry.get(name);
      c.meaning = hint != hints().end() ? hint->second.meaning : std::string(effect.summary());
      const Model cand = warm.with_effect(name, /*at_neutral=*/true, registry);
      std::vector<std::size_t> added;
      for (const auto& p : effect.parameters()) {
        const std::size_t j = cand.index(p.name);
        if (cand.calibrated(j)) {
          added.push_back(j);
          c.added_parameters.emplace_back(p.name);
        }
      }
      AssessOptions warm_options = o.assess;
      warm_options.population_starts = o.assess.warm_starts;
      warm_options.refine_start = true;
      if (threads > 1) warm_options.fit.threads = 1;
      c.assessment = assess(cand, shape, set, warm_options);
      for (std::size_t j : added) c.added_values.push_back(c.assessment.population.params[j]);
      c.adequacy = adequacy(c.assessment, b.floor);
      c.heldout_error = c.assessment.heldout.error.mean;
      c.heldout_se = c.assessment.heldout.error.se;
      std::vector<double> drops(set.size());
      for (std::size_t i = 0; i < set.size(); ++i)
        drops[i] = base.heldout.per_release[i] - c.assessment.heldout.per_release[i];
      const MeanSe dm = mean_se(drops);
      c.error_drop = dm.mean;
      c.drop_se = dm.se;
      c.penalty = static_cast<double>(added.size()) * b.floor.value.mean / std::max(1.0, n_train);
      c.penalised_heldout = c.heldout_error + c.penalty;
      c.supported = c.error_drop - c.penalty > o.z * c.drop_se && c.error_drop > c.penalty;
      DiagnoseOptions so = o;
      if (threads > 1) so.assess.fit.threads = 1;
      c.signature_r = signature_r(dirs, cand, shape, set, added, so);
      c.evidence = evidence_of(c, b, base);
    } catch (const std::exception& e) {
      c.error = e.what();
      c.penalised_heldout = INFINITY;
      c.heldout_error = NAN;
      c.evidence = std::string("could not be tried: ") + e.what();
      if (c.meaning.empty()) c.meaning = name;
    }
    tried[k] = std::move(c);
    progress.advance();
  }
  d.ranking = std::move(tried);
  progress.finish();
  // Supported effects first, then by penalised held-out error.
  std::stable_sort(d.ranking.begin(), d.ranking.end(), [](const Candidate& x, const Candidate& y) {
    if (x.supported != y.supported) return x.supported;
    return x.penalised_heldout < y.penalised_heldout;
  });

  const bool adequate = b.adequacy.adequate;
  d.verdict = adequate ? "adequate" : "missing physics";
  const Candidate* best =
      !d.ranking.empty() && d.ranking.front().supported ? &d.ranking.front() : nullptr;
  if (adequate) {
    d.summary = fmt::format(
        "The model is adequate: held-out error {:.4g} is within the noise floor {:.4g} ({}; "
        "threshold {:.4g}).",
        base.heldout.error.mean, b.floor.value.mean, b.floor.source, b.adequacy.threshold);
    if (best)
      d.summary += fmt::format(" {} still lowers the held-out error ({:.3g} +- {:.2g}).",
                               best->effect, best->error_drop, best->drop_se);
    else
      d.summary += " No effect in the catalog is supported.";
  } else if (best) {
    d.summary = fmt::format(
        "Missing physics: held-out error {:.4g} is {:.2f} x the noise floor {:.4g}. Best "
        "candidate: {} ({}), held-out error {:.4g}{}.",
        base.heldout.error.mean, b.adequacy.ratio, b.floor.value.mean, best->effect, best->meaning,
        best->heldout_error,
        best->adequacy.adequate ? ", within the noise floor" : ", still above the noise floor");
  } else {
    d.summary = fmt::format(
        "Missing physics: held-out error {:.4g} is {:.2f} x the noise floor {:.4g}, but no effect "
        "in the catalog is supported.",
        base.heldout.error.mean, b.adequacy.ratio, b.floor.value.mean);
  }
  if (best)
    d.unexplained = unexplained_after(best->assessment, b.floor, best->adequacy, b.features,
                                      o.trends, "after adding " + best->effect);
  else
    d.unexplained =
        unexplained_after(base, b.floor, b.adequacy, b.features, o.trends, "base model");
  d.seconds = seconds_since(t0) + b.seconds;
  return d;
}

Ladder ladder(const Model& model, const Shape& shape, const ImpactSet& set,
              const std::vector<std::string>& adds, const DiagnoseOptions& options) {
  DiagnoseOptions o = options;
  o.assess = resolve_scale(set, options.assess);
  Ladder l;
  const EffectRegistry& registry = registry_of(o);
  Model current = model;
  Progress progress("ladder", adds.size() + 1, o.progress);
  for (std::size_t r = 0; r <= adds.size(); ++r) {
    Rung rung;
    if (r > 0) {
      rung.added = adds[r - 1];
      try {
        current = current.with_effect(rung.added, /*at_neutral=*/true, registry);
      } catch (const std::exception& e) {
        throw InputError("<command line>", 0, "--add", e.what());
      }
    }
    progress.status(r == 0 ? "base" : rung.added);
    rung.effects = current.effect_names();
    AssessOptions rung_options = o.assess;
    if (r > 0) {
      rung_options.population_starts = o.assess.warm_starts;
      rung_options.refine_start = true;
    }
    rung.assessment = assess(current, shape, set, rung_options);
    current = with_values(current, rung.assessment.population.params);
    if (r == 0)
      l.floor = noise_floor(current, shape, rung.assessment.population.params, set,
                            rung.assessment.use, o.assess);
    rung.adequacy = adequacy(rung.assessment, l.floor);
    l.rungs.push_back(std::move(rung));
    progress.advance();
  }
  progress.finish();
  return l;
}

Ladder auto_ladder(const Model& model, const Shape& shape, const ImpactSet& set, int max_rounds,
                   const DiagnoseOptions& o, const Diagnosis* first) {
  Ladder l;
  Model current = model;
  for (int round = 0;; ++round) {
    Diagnosis d = round == 0 && first ? *first : diagnose(current, shape, set, o);
    if (round == 0) {
      l.floor = d.baseline.floor;
      Rung base;
      base.effects = current.effect_names();
      base.assessment = d.baseline.base;
      base.adequacy = d.baseline.adequacy;
      l.rungs.push_back(std::move(base));
    }
    const bool adequate = adequacy(d.baseline.base, l.floor).adequate;
    const bool supported = !d.ranking.empty() && d.ranking.front().supported;
    l.rounds.push_back(d);
    if (adequate) {
      l.stop_reason = "the model is adequate (held-out error within the noise floor)";
      break;
    }
    if (!supported) {
      l.stop_reason = "no effect in the catalog is supported";
      break;
    }
    if (round >= max_rounds) {
      l.stop_reason = fmt::format("stopped after {} rounds", max_rounds);
      break;
    }
    const Candidate& best = d.ranking.front();
    const EffectRegistry& registry = registry_of(o);
    current = with_values(current.with_effect(best.effect, true, registry),
                          best.assessment.population.params);
    Rung rung;
    rung.added = best.effect;
    rung.effects = current.effect_names();
    rung.assessment = best.assessment;
    rung.adequacy = adequacy(best.assessment, l.floor);
    l.rungs.push_back(std::move(rung));
  }
  return l;
}

nlohmann::json to_json(const Assessment& a, const NoiseFloor& floor) {
  nlohmann::json params = nlohmann::json::object();
  for (std::size_t i = 0; i < a.population.names.size(); ++i)
    params[a.population.names[i]] = a.population.params[i];
  const Adequacy q = adequacy(a, floor);
  return {{"model", a.effects},
          {"calibrated", a.calibrated},
          {"parameters", params},
          {"insample_error", a.insample.error.mean},
          {"insample_se", a.insample.error.se},
          {"heldout_error", a.heldout.error.mean},
          {"heldout_se", a.heldout.error.se},
          {"folds", a.folds},
          {"insample_per_component", to_json(a.insample.term_mean, a.use)},
          {"heldout_per_component", to_json(a.heldout.term_mean, a.use)},
          {"heldout_rmse", to_json(a.heldout.rmse, a.use)},
          {"adequate", q.adequate},
          {"ratio_to_floor", q.ratio},
          {"adequacy_threshold", q.threshold},
          {"excess_over_floor", q.excess},
          {"excess_se", q.excess_se},
          {"seconds", a.seconds}};
}

nlohmann::json to_json(const Baseline& b, const ImpactSet& set) {
  nlohmann::json j = to_json(b.base, b.floor);
  j["noise_floor"] = to_json(b.floor, b.base.use);
  j["error_denominator_floors"] = to_json(b.error_floors, b.base.use);
  nlohmann::json releases = nlohmann::json::array();
  for (std::size_t i = 0; i < set.size(); ++i) {
    nlohmann::json r = {
        {"id", set.impacts[i].id},
        {"heldout_error", b.base.heldout.per_release[i]},
        {"insample_error", b.base.insample.per_release[i]},
        {"noise_floor", b.floor.per_release[i]},
        {"heldout_predicted", to_json(b.base.heldout_predictions[i].value, b.base.use)},
        {"heldout_residual", to_json(b.base.heldout.residual[i], b.base.use)}};
    if (!b.release_fits.empty()) {
      nlohmann::json p = nlohmann::json::object();
      const auto& f = b.release_fits[i];
      for (std::size_t c : f.calibrated) {
        nlohmann::json e = {{"value", f.params[c]}};
        if (const auto* iv = f.interval(f.names[c])) {
          e["interval"] = {iv->lo, iv->hi};
          e["identifiability"] = fit::identifiability_name(iv->status);
        }
        p[f.names[c]] = e;
      }
      r["release_fit"] = {{"error", f.error}, {"params", p}};
      if (std::isfinite(f.alpha_rad)) r["release_fit"]["alpha_in_rad"] = f.alpha_rad;
    }
    releases.push_back(r);
  }
  j["releases"] = releases;
  nlohmann::json regimes = nlohmann::json::array();
  for (const auto& r : b.regimes)
    regimes.push_back({{"name", r.name},
                       {"n", r.releases.size()},
                       {"heldout_error", r.heldout.mean},
                       {"heldout_se", r.heldout.se},
                       {"noise_floor", r.floor.mean}});
  j["regimes"] = regimes;
  nlohmann::json ks = nlohmann::json::object();
  for (int k = 0; k < kObservables; ++k)
    if (b.base.use[k])
      ks[kObservableNames[k]] = {{"statistic", b.ks[k].statistic}, {"p_value", b.ks[k].p_value}};
  j["ks"] = ks;
  j["residual_trends"] = to_json(b.residual_trends, true);
  j["parameter_trends"] = to_json(b.parameter_trends, true);
  j["features"] = nlohmann::json::array();
  for (const auto& f : b.features)
    j["features"].push_back({{"name", f.name}, {"label", f.label}, {"simulated", f.simulated}});
  return j;
}

nlohmann::json to_json(const Candidate& c, const std::array<bool, kObservables>& use) {
  nlohmann::json params = nlohmann::json::object();
  for (std::size_t i = 0; i < c.added_parameters.size() && i < c.added_values.size(); ++i)
    params[c.added_parameters[i]] = c.added_values[i];
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  nlohmann::json j = {{"effect", c.effect},
                      {"heldout_error", num(c.heldout_error)},
                      {"error_drop", num(c.error_drop)},
                      {"evidence", c.evidence},
                      {"drop_se", num(c.drop_se)},
                      {"penalty", num(c.penalty)},
                      {"penalised_heldout_error", num(c.penalised_heldout)},
                      {"supported", c.supported},
                      {"adequate_after", c.adequacy.adequate},
                      {"signature_r", num(c.signature_r)},
                      {"meaning", c.meaning},
                      {"parameters", params}};
  if (c.error.empty()) {
    j["insample_error"] = c.assessment.insample.error.mean;
    j["heldout_per_component"] = to_json(c.assessment.heldout.term_mean, use);
  } else {
    j["error"] = c.error;
  }
  return j;
}

nlohmann::json to_json(const Diagnosis& d) {
  const Baseline& b = d.baseline;
  nlohmann::json ranking = nlohmann::json::array();
  for (const auto& c : d.ranking) ranking.push_back(to_json(c, b.base.use));
  return {{"verdict", d.verdict},
          {"noise_floor", b.floor.value.mean},
          {"base_error", b.base.heldout.error.mean},
          {"ranking", ranking},
          {"summary", d.summary},
          {"unexplained", d.unexplained},
          {"noise_floor_source", b.floor.source},
          {"noise_floor_detail", to_json(b.floor, b.base.use)},
          {"error_denominator_floors", to_json(b.error_floors, b.base.use)},
          {"base", to_json(b.base, b.floor)},
          {"residual_trends", to_json(b.residual_trends, true)},
          {"parameter_trends", to_json(b.parameter_trends, true)},
          {"observables", to_json(Obs{1, 1, 1, 1, 1}, b.base.use)},
          {"seconds", d.seconds}};
}

nlohmann::json to_json(const Ladder& l) {
  nlohmann::json rungs = nlohmann::json::array();
  for (const auto& r : l.rungs) {
    nlohmann::json j = to_json(r.assessment, l.floor);
    j["added"] = r.added.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.added);
    rungs.push_back(j);
  }
  nlohmann::json j = {
      {"rungs", rungs},
      {"noise_floor", l.floor.value.mean},
      {"noise_floor_detail",
       to_json(l.floor, l.rungs.empty()
                            ? std::array<bool, kObservables>{true, true, true, false, false}
                            : l.rungs.front().assessment.use)}};
  if (!l.rounds.empty()) {
    nlohmann::json rounds = nlohmann::json::array();
    for (const auto& d : l.rounds) {
      nlohmann::json r = {{"verdict", d.verdict}, {"summary", d.summary}};
      if (!d.ranking.empty())
        r["best"] = {{"effect", d.ranking.front().effect},
                     {"supported", d.ranking.front().supported},
                     {"error_drop", d.ranking.front().error_drop},
                     {"drop_se", d.ranking.front().drop_se}};
      rounds.push_back(r);
    }
    j["rounds"] = rounds;
    j["stop_reason"] = l.stop_reason;
  }
  return j;
}

}  // namespace ricochet::diagnosis
