// The force-history error of a calibrated model and the discovered law as a model
// (force_history.hpp).
#include "diagnosis/force_history.hpp"
#include "common/json_number.hpp"
#include "common/nan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "effects/force_term.hpp"
#include "report/plot.hpp"
#include "stats/track_summary.hpp"

namespace ricochet::diagnosis {

ForceHistoryError force_history_error(const Model& model, const Shape& shape, const Assessment& a,
                                      const std::vector<std::optional<MeasuredHistory>>& histories,
                                      const EngineOptions& engine) {
  if (histories.size() != a.cv.n)
    throw std::invalid_argument(
        fmt::format("force_history_error: {} histories for a set of {}", histories.size(), a.cv.n));
  if (a.fold_params.size() != a.cv.splits())
    throw std::invalid_argument("force_history_error: the assessment has no fold fits");
  ForceHistoryError e;
  e.releases = history_count(histories);
  ResidualSquares in;
  for (const auto& h : histories)
    if (h) {
      const ReleaseResidual r = force_residual(*h, model, shape, a.population.params, engine);
      e.samples += r.samples.size();
      in.add(r);
    }
  // The splits are independent: each evaluates its own fit along its own test releases. Kept
  // per (split, test release), so that each release's held-out squares (over the repeats that
  // held it out) give the figure's standard error over releases.
  std::vector<std::vector<ResidualSquares>> per_split(a.cv.splits());
#pragma omp parallel for schedule(dynamic)
  for (std::size_t s = 0; s < a.cv.splits(); ++s) {
    // A split that calibrated its own model (assess with a SplitModel) is evaluated with it.
    const Model& ms = a.fold_models.empty() ? model : a.fold_models[s];
    per_split[s].resize(a.cv.test[s].size());
    for (std::size_t k = 0; k < a.cv.test[s].size(); ++k)
      if (const std::size_t i = a.cv.test[s][k]; histories[i])
        per_split[s][k].add(force_residual(*histories[i], ms, shape, a.fold_params[s], engine));
  }
  std::vector<ResidualSquares> per_release(a.cv.n);
  ResidualSquares out;
  for (std::size_t s = 0; s < a.cv.splits(); ++s)
    for (std::size_t k = 0; k < a.cv.test[s].size(); ++k) {
      per_release[a.cv.test[s][k]].add(per_split[s][k]);
      out.add(per_split[s][k]);
    }
  e.insample_rms = in.rms();
  e.heldout_rms = out.rms();
  for (std::size_t c = 0; c < kForceComponents; ++c) {
    std::vector<double> ss;
    std::vector<std::size_t> n;
    for (const ResidualSquares& r : per_release) {
      ss.push_back(r.sum[c]);
      n.push_back(r.n[c]);
    }
    e.heldout_se[c] = pooled_rms_se(ss, n);
  }
  return e;
}

double pooled_rms_se(std::span<const double> ss, std::span<const std::size_t> n) {
  if (ss.size() != n.size()) throw std::invalid_argument("pooled_rms_se: sizes differ");
  double sum_ss = 0, sum_n = 0;
  std::size_t m = 0;
  for (std::size_t i = 0; i < ss.size(); ++i)
    if (n[i] > 0) {
      sum_ss += ss[i];
      sum_n += static_cast<double>(n[i]);
      ++m;
    }
  if (m < 2 || !(sum_ss > 0)) return kNaN;
  const double r = sum_ss / sum_n;
  double dev = 0;
  for (std::size_t i = 0; i < ss.size(); ++i)
    if (n[i] > 0) {
      const double d = ss[i] - r * static_cast<double>(n[i]);
      dev += d * d;
    }
  const double md = static_cast<double>(m);
  const double var_r = md / (md - 1) * dev / (sum_n * sum_n);
  return std::sqrt(var_r) / (2 * std::sqrt(r));
}

std::vector<std::vector<double>> release_params_of(const Diagnosis& d, std::size_t releases) {
  std::vector<std::vector<double>> out;
  if (d.baseline.release_fits.size() == releases)
    for (const auto& f : d.baseline.release_fits) out.push_back(f.params);
  return out;
}

std::optional<ForceLawReport> force_law_of(const Diagnosis& d, const std::string& data,
                                           const ImpactSet& set, const Shape& shape,
                                           const Model& model, const EngineOptions& engine) {
  return force_law_from_tracks(data, set, shape, model, d.baseline.base.population.params, engine,
                               {}, release_params_of(d, set.size()));
}

std::vector<ForceHistoryError> ladder_force_history(
    const Model& base, const Ladder& l, const Shape& shape,
    const std::vector<std::optional<MeasuredHistory>>& histories, const EngineOptions& engine) {
  std::vector<ForceHistoryError> out;
  if (history_count(histories) < 2) return out;
  for (std::size_t r = 0; r < l.rungs.size(); ++r)
    out.push_back(force_history_error(rung_model(base, l, r), shape, l.rungs[r].assessment,
                                      histories, engine));
  return out;
}

nlohmann::json to_json(const ForceHistoryError& e) {
  const auto by_component = [](const std::array<double, kForceComponents>& v) {
    nlohmann::json j = nlohmann::json::object();
    for (std::size_t c = 0; c < kForceComponents; ++c)
      j[std::string(component_name(static_cast<ForceComponent>(c)))] = finite_or_null(v[c]);
    return j;
  };
  return {{"insample_rms", by_component(e.insample_rms)},
          {"heldout_rms", by_component(e.heldout_rms)},
          {"heldout_se", by_component(e.heldout_se)},
          {"releases", e.releases},
          {"samples", e.samples}};
}

namespace {

// One history from its contact's start: time since it [s] and per record the normal force, the
// tangential force and the moment about the lowest point; `window` the contact's length [s].
struct AlignedContact {
  std::vector<double> t;
  std::vector<std::array<double, kForceComponents>> f;
  double window = 0;
  // The components at time tau since the start: interpolated between records, 0 beyond the
  // last one (the block in flight).
  std::array<double, kForceComponents> at(double tau) const {
    if (tau > t.back()) return {};
    const auto hi = std::upper_bound(t.begin(), t.end(), tau);
    if (hi == t.begin()) return f.front();
    if (hi == t.end()) return f.back();
    const std::size_t k = static_cast<std::size_t>(hi - t.begin());
    const double w = (tau - t[k - 1]) / (t[k] - t[k - 1]);
    std::array<double, kForceComponents> out;
    for (std::size_t c = 0; c < kForceComponents; ++c)
      out[c] = (1.0 - w) * f[k - 1][c] + w * f[k][c];
    return out;
  }
};

std::optional<AlignedContact> aligned_contact(const MeasuredHistory& h, const Shape& shape) {
  // The forces are the lab block's (measured_history scales them), so is the weight.
  const auto w = stats::contact_window(h.fx_N, h.fy_N, shape.mass_kg);
  if (!w) return std::nullopt;
  const std::size_t first = w->first, last = w->last;
  AlignedContact a;
  const double t0 = h.path[first].t_s;
  a.window = h.path[last].t_s - t0;
  for (std::size_t i = first; i < h.path.size(); ++i) {
    const auto r = shape.lowest_point(h.path[i].theta_rad);
    a.t.push_back(h.path[i].t_s - t0);
    a.f.push_back({h.fy_N[i], h.fx_N[i], h.torque_Nm[i] - (r[0] * h.fy_N[i] - r[1] * h.fx_N[i])});
  }
  return a;
}

}  // namespace

ForceHistoryScatter force_history_scatter(
    const ImpactSet& set, const std::vector<std::optional<MeasuredHistory>>& histories,
    const Shape& shape) {
  if (histories.size() != set.size())
    throw std::invalid_argument(fmt::format("force_history_scatter: {} histories for a set of {}",
                                            histories.size(), set.size()));
  ForceHistoryScatter out;
  std::array<double, kForceComponents> squares{};
  std::array<std::size_t, kForceComponents> dof{};
  for (const auto& group : replicate_groups(set)) {
    std::vector<AlignedContact> members;
    for (std::size_t i : group)
      if (histories[i])
        if (auto a = aligned_contact(*histories[i], shape); a && a->t.size() >= 2)
          members.push_back(std::move(*a));
    if (members.size() < 2) continue;
    ++out.groups;
    out.histories += members.size();
    // The group's grid: its finest record interval, up to the end of its longest contact.
    double step = std::numeric_limits<double>::infinity(), end = 0;
    for (const auto& m : members) {
      step = std::min(step, (m.t.back() - m.t.front()) / static_cast<double>(m.t.size() - 1));
      end = std::max(end, m.window);
    }
    // (The tolerance keeps a window of a whole number of steps whole despite rounding.)
    const auto times = static_cast<std::size_t>(std::floor(end / step + 1e-9)) + 1;
    out.samples += times;
    std::vector<std::array<double, kForceComponents>> v(members.size());
    for (std::size_t k = 0; k < times; ++k) {
      for (std::size_t j = 0; j < members.size(); ++j)
        v[j] = members[j].at(static_cast<double>(k) * step);
      for (std::size_t c = 0; c < kForceComponents; ++c) {
        std::size_t n = 0;
        double mean = 0;
        for (const auto& x : v)
          if (std::isfinite(x[c])) {
            mean += x[c];
            ++n;
          }
        if (n < 2) continue;
        mean /= static_cast<double>(n);
        for (const auto& x : v)
          if (std::isfinite(x[c])) squares[c] += (x[c] - mean) * (x[c] - mean);
        dof[c] += n - 1;
      }
    }
  }
  for (std::size_t c = 0; c < kForceComponents; ++c)
    out.rms[c] = dof[c] > 0 ? std::sqrt(squares[c] / static_cast<double>(dof[c])) : kNaN;
  return out;
}

nlohmann::json to_json(const ForceHistoryScatter& s) {
  nlohmann::json rms = nlohmann::json::object();
  for (std::size_t c = 0; c < kForceComponents; ++c)
    rms[std::string(component_name(static_cast<ForceComponent>(c)))] = finite_or_null(s.rms[c]);
  return {{"rms", rms},
          {"groups", s.groups},
          {"histories", s.histories},
          {"samples", s.samples},
          {"source", s.source},
          {"where", s.where},
          {"moment_about", "the block's lowest point"}};
}

Model with_force_law(const Model& base, std::span<const double> base_params,
                     const ForceLawReport& report, std::vector<std::string>* warnings) {
  Model m = base;
  if (!base_params.empty()) m.set_values({base_params.begin(), base_params.end()});
  for (const ComponentLaw& law : report.laws)
    for (const DiscoveredTerm& t : law.terms) {
      if (!t.selected) continue;
      const std::string effect = effects::force_term_effect_name(*t.term);
      const std::string name = effects::force_term_parameter_name(*t.term);
      Model with = m.with_effect(effect, /*at_neutral=*/true);
      const std::size_t i = with.index(name);
      const double v = std::clamp(t.coefficient, with.lower(i), with.upper(i));
      // Clamped to its neutral 0 (a negative drag or hysteresis) the term would do nothing:
      // it is left out rather than carried at zero.
      if (v != t.coefficient && warnings)
        warnings->push_back(fmt::format(
            "{} = {:.4g} {} is outside [{:.4g}, {:.4g}]: {} (effects/force_term.hpp: a negative "
            "drag or hysteresis would make energy)",
            name, t.coefficient, t.term->unit, with.lower(i), with.upper(i),
            v == 0.0 ? std::string("left out") : fmt::format("written as {:.4g}", v)));
      if (v == 0.0) continue;
      with.set(name, v);
      with.set_calibrated(name, false);  // the histories identify it, not the rebounds
      m = std::move(with);
    }
  return m;
}

std::optional<NamedFigure> force_residual_figure(
    const std::vector<std::optional<MeasuredHistory>>& histories, const Model& model,
    const Shape& shape, std::span<const double> params,
    const std::vector<std::vector<double>>& release_params, const ForceLawReport& report,
    const EngineOptions& engine, const std::string& title) {
  if (history_count(histories) < 2) return std::nullopt;
  const Model with_law = with_force_law(model, params, report);
  if (with_law.effect_names() == model.effect_names()) return std::nullopt;
  report::Series before, after;
  before.title = "the model";
  after.title = "with the discovered law";
  before.style = after.style = "points";
  before.color = report::colour::kVermillion;
  after.color = report::colour::kBlue;
  ResidualSquares sq_before, sq_after;
  for (std::size_t i = 0; i < histories.size(); ++i) {
    if (!histories[i]) continue;
    std::vector<double> own(params.begin(), params.end());
    if (i < release_params.size() && !release_params[i].empty()) own = release_params[i];
    // The release's own calibration with the law's terms at their discovered values.
    const Model at_own = with_force_law(model, own, report);
    const ReleaseResidual b = force_residual(*histories[i], model, shape, own, engine);
    const ReleaseResidual a = force_residual(*histories[i], at_own, shape, at_own.values(), engine);
    sq_before.add(b);
    sq_after.add(a);
    for (const auto& [r, series] : {std::pair{&b, &before}, std::pair{&a, &after}}) {
      if (r->t_s.empty()) continue;
      for (std::size_t k = 0; k < r->t_s.size(); ++k) {
        series->x.push_back(1e3 * (r->t_s[k] - r->t_s.front()));
        series->y.push_back(r->residual[k][0]);
      }
    }
  }
  const double rms_before = sq_before.rms()[0], rms_after = sq_after.rms()[0];
  NamedFigure f;
  f.stem = "force-residual";
  f.figure.title = title + ": the normal force the model leaves, before and after the law";
  report::Panel p;
  p.xlabel = "time since the contact starts [ms]";
  p.ylabel = "measured - model normal force [N]";
  p.series = {before, after};
  f.figure.panels = {p};
  f.caption = fmt::format(
      "The normal contact force the model leaves along each release's own measured path (every "
      "contact sample of {} releases), each release at its own calibration ({}), before and "
      "after the force law discovered on these histories ({}). RMS {:.4g} N before, {:.4g} N "
      "after (in-sample: the law's terms were fitted to these residuals; their leak-free "
      "held-out figure is the discovery's, in the diagnosis).",
      history_count(histories), report.base, found_law_text(report), rms_before, rms_after);
  return f;
}

}  // namespace ricochet::diagnosis
