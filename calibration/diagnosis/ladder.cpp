// ladder() and auto_ladder(): models of growing physics, each judged by its held-out error
// (diagnose.hpp).
#include <fmt/format.h>

#include <optional>

#include "common/error.hpp"
#include "common/progress.hpp"
#include "diagnosis/diagnose.hpp"
#include "diagnosis/force_history.hpp"
#include "diagnosis/scatter.hpp"
#include "diagnosis/signature.hpp"
#include "fit/fit.hpp"

namespace ricochet::diagnosis {
using detail::left_neutral;
using detail::registry_of;

Ladder ladder(const Model& model, const Shape& shape, const ImpactSet& set,
              const std::vector<std::string>& adds, const DiagnoseOptions& options) {
  require_valid(options.problems(), "diagnosis::ladder");
  const DiagnoseOptions o = resolve_scale(set, options);
  Ladder l;
  const EffectRegistry& registry = registry_of(o);
  // The base model as calibrated on this set (kn too when its contact features enter the error).
  Model current = calibration_model_for(model, set, o.assess);
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
    // Each rung's splits start from the previous rung's optima on the same training releases.
    rung.assessment =
        assess(current, shape, set, rung_options, r > 0 ? &l.rungs.back().assessment : nullptr);
    current = with_values(current, rung.assessment.population.params);
    if (r > 0) rung.law = detail::law_of(current, current.values(), {rung.added}, registry);
    if (r == 0)  // the measurement floor as compare() has it (fitted when nothing declares it)
      l.floor = population_scatter(current, shape, set, rung.assessment,
                                   noise_floor(current, shape, rung.assessment.population.params,
                                               set, rung.assessment.use, o.assess),
                                   o.assess)
                    .measurement;
    rung.adequacy = adequacy(rung.assessment, l.floor);
    l.rungs.push_back(std::move(rung));
    progress.advance();
  }
  progress.finish();
  return l;
}

namespace {

// The selected terms' names of a report, component by component: two laws are "the same"
// when these agree (coefficients aside).
std::vector<std::string> selected_terms(const ForceLawReport& r) {
  std::vector<std::string> names;
  for (const ComponentLaw& law : r.laws)
    for (const DiscoveredTerm& t : law.terms)
      if (t.selected)
        names.push_back(fmt::format("{}:{}", component_name(law.component), t.term->name));
  return names;
}

}  // namespace

std::optional<ForceLawReport> add_force_law_rung(Ladder& l, const Model& base, const Shape& shape,
                                                 const ImpactSet& set, const std::string& data,
                                                 const DiagnoseOptions& options,
                                                 std::span<const ForceTerm* const> named) {
  if (l.rungs.empty()) throw std::invalid_argument("add_force_law_rung: the ladder has no rung");
  const DiagnoseOptions o = resolve_scale(set, options);
  const Model last = rung_model(base, l, l.rungs.size() - 1, registry_of(o));
  // Each release at its own calibration, as diagnose: the constants' scatter is not a force.
  // A release's own fit reads only its own rebound, so the splits below may use it.
  fit::FitOptions fo = fit_options_for(set, o.assess);
  fo.intervals = false;
  std::vector<std::vector<double>> release_params;
  for (const auto& f :
       fit::calibrate_releases(calibration_model_for(last, set, o.assess), shape, set, fo))
    release_params.push_back(f.params);
  const auto histories = measured_histories(data, set, shape);
  const EngineOptions& engine = o.assess.fit.engine;
  auto report = force_law_from_histories(histories, shape, last, last.values(), engine, {},
                                         release_params, named);
  if (!report) return report;
  std::vector<std::string> warnings;
  const Model with_law = with_force_law(last, last.values(), *report, &warnings);
  Rung rung;
  for (const std::string& e : with_law.effect_names())
    if (!last.has_effect(e)) rung.added += (rung.added.empty() ? "" : "+") + e;
  rung.law = found_law_text(*report);
  for (const std::string& w : warnings) rung.law += " [" + w + "]";
  if (rung.added.empty()) return report;
  rung.effects = with_law.effect_names();
  // Leak-free: split j's model carries the law its training histories give.
  const std::vector<std::string> full_terms = selected_terms(*report);
  const SplitModel split_model = [&](const std::vector<std::size_t>& train) {
    std::vector<std::optional<MeasuredHistory>> h;
    std::vector<std::vector<double>> p;
    for (std::size_t i : train) {
      h.push_back(histories[i]);
      p.push_back(release_params[i]);
    }
    const auto r = force_law_from_histories(h, shape, last, last.values(), engine, {}, p, named);
    ++rung.split_discoveries;
    if (!r) return last;
    if (selected_terms(*r) == full_terms) ++rung.split_same_terms;
    return with_force_law(last, last.values(), *r);
  };
  rung.assessment = assess(with_law, shape, set, o.assess, split_model);
  rung.adequacy = adequacy(rung.assessment, l.floor);
  l.rungs.push_back(std::move(rung));
  return report;
}

Ladder auto_ladder(const Model& model, const Shape& shape, const ImpactSet& set, int max_rounds,
                   const DiagnoseOptions& o, const Diagnosis* first) {
  require_valid(o.problems(), "diagnosis::auto_ladder");
  Ladder l;
  Model current = model;
  // The previous round's best candidate, calibrated leak-free split by split: the next round's
  // folds refine its fold optima (issue 31, 5a), not the full-set optimum in `current`.
  std::optional<Assessment> previous;
  for (int round = 0;; ++round) {
    Diagnosis d =
        round == 0 && first ? *first
        : previous ? diagnose(compare(current, shape, set, o, &*previous), current, shape, set, o)
                   : diagnose(current, shape, set, o);
    if (round == 0) {
      l.floor = d.baseline.floor;
      Rung base;
      base.effects = current.effect_names();
      base.assessment = d.baseline.base;
      base.adequacy = d.baseline.adequacy;
      l.rungs.push_back(std::move(base));
    }
    const bool supported = !d.ranking.empty() && d.ranking.front().supported;
    const std::string verdict = d.verdict;
    l.rounds.push_back(d);
    if (!supported) {
      l.stop_reason = verdict == "adequate"
                          ? "the model is adequate (held-out error within the noise floor) and no "
                            "candidate is supported"
                      : verdict == "inconclusive"
                          ? "no candidate is supported and the held-out error is within the noise "
                            "floor, but these data could hide a law of some family (the "
                            "verdict is inconclusive)"
                      : verdict == "scatter"
                          ? "no candidate is supported: the excess over the measurement floor is "
                            "release-to-release scatter"
                          : "no candidate is supported, but a residual trend remains (missing "
                            "physics beyond the candidates)";
      break;
    }
    if (round >= max_rounds) {
      l.stop_reason = fmt::format("stopped after {} rounds", max_rounds);
      break;
    }
    const Candidate& best = d.ranking.front();
    const EffectRegistry& registry = registry_of(o);
    Model next = current;
    for (const auto& e : best.effects) next = next.with_effect(e, true, registry);
    // A supported candidate whose own parameters the fit left at neutral adds nothing: the
    // held-out error it "gained" came from refitting the other parameters (seen on a resolved
    // campaign, where they went into the corners of their box; docs/diagnosis.md).
    if (left_neutral(next, best.assessment.population.params, best.effects, registry)) {
      l.stop_reason = fmt::format(
          "the best supported candidate, {}, was left at its neutral value by the fit: it adds "
          "nothing (the error fell through the other parameters), so it is not added",
          best.effect);
      break;
    }
    current = with_values(next, best.assessment.population.params);
    previous = best.assessment;
    Rung rung;
    rung.added = best.effect;
    rung.law = best.law;
    rung.effects = current.effect_names();
    rung.assessment = best.assessment;
    rung.adequacy = adequacy(best.assessment, l.floor);
    l.rungs.push_back(std::move(rung));
  }
  return l;
}

Model rung_model(const Model& base, const Ladder& l, std::size_t rung,
                 const EffectRegistry& registry) {
  Model m = base;
  for (std::size_t r = 1; r <= rung && r < l.rungs.size(); ++r) {
    const std::string& added = l.rungs[r].added;
    for (std::size_t a = 0, b; a <= added.size(); a = b + 1) {
      b = added.find('+', a);
      if (b == std::string::npos) b = added.size();
      m = m.with_effect(added.substr(a, b - a), /*at_neutral=*/true, registry);
    }
  }
  if (rung < l.rungs.size()) m.set_values(l.rungs[rung].assessment.population.params);
  return m;
}

Model ladder_model(const Model& base, const Ladder& l, const EffectRegistry& registry) {
  return rung_model(base, l, l.rungs.empty() ? 0 : l.rungs.size() - 1, registry);
}

}  // namespace ricochet::diagnosis
