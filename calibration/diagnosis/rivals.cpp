// Rival laws of a design of throws, calibrated on the set (rivals.hpp).
#include "diagnosis/rivals.hpp"

#include <omp.h>

#include <algorithm>
#include <set>

#include "common/error.hpp"
#include "diagnosis/signature.hpp"

namespace ricochet::diagnosis {

std::string rival_name(const std::vector<std::string>& effects) {
  if (effects.empty()) return "none";
  std::string name;
  for (const auto& e : effects) name += (name.empty() ? "" : "+") + e;
  return name;
}

std::vector<std::vector<std::string>> parse_rivals(std::span<const std::string> names,
                                                   const Model& base,
                                                   const EffectRegistry& registry,
                                                   const std::string& option) {
  const auto bad = [&](const std::string& what) {
    return InputError("<command line>", 0, option, what);
  };
  std::vector<std::vector<std::string>> out;
  std::set<std::string> seen;
  for (const std::string& name : names) {
    std::vector<std::string> effects;
    if (name != "none") {
      std::size_t start = 0;
      while (true) {
        const std::size_t plus = name.find('+', start);
        effects.push_back(name.substr(start, plus == std::string::npos ? plus : plus - start));
        if (plus == std::string::npos) break;
        start = plus + 1;
      }
      if (effects.size() > 2) throw bad("'" + name + "': a rival adds at most two effects (a+b)");
      for (const auto& e : effects) {
        if (!registry.contains(e)) {
          std::string known = "none";
          for (const auto& k : registry.names())
            if (!base.has_effect(k)) known += ", " + k;
          throw bad("unknown rival '" + e + "'; known: " + known + " (or a+b for a pair)");
        }
        if (base.has_effect(e))
          throw bad("'" + e + "' is already in the base model: it is the rival 'none'");
      }
      if (effects.size() == 2 && effects[0] == effects[1])
        throw bad("'" + name + "': the same effect twice");
    }
    // "b+a" is the same law as "a+b".
    std::vector<std::string> key = effects;
    std::sort(key.begin(), key.end());
    if (!seen.insert(rival_name(key)).second) throw bad("rival '" + name + "' is named twice");
    out.push_back(std::move(effects));
  }
  if (out.size() < 2)
    throw bad(
        "name at least two rivals (e.g. none,rate_restitution): a design decides between "
        "laws");
  return out;
}

namespace {

double mean_error(const fit::PopulationFit& f, std::size_t n) {
  return n > 0 ? f.error / static_cast<double>(n) : NAN;
}

// The base model plus `effects` at neutral, from the calibrated base `warm`, calibrated on the
// set as assess() calibrates a warm candidate (rivals.hpp).
Rival calibrate_one(const Model& warm, const std::vector<std::string>& effects, const Shape& shape,
                    const ImpactSet& set, const AssessOptions& o, const EffectRegistry& registry,
                    int threads) {
  Rival r;
  r.name = rival_name(effects);
  r.effects = effects;
  Model start = warm;
  for (const auto& e : effects) start = start.with_effect(e, /*at_neutral=*/true, registry);
  start = calibration_model_for(start, set, o);
  fit::FitOptions fo = fit_options_for(set, o);
  fo.intervals = false;
  fo.threads = threads;
  fo.starts = o.warm_starts;
  r.fit = fit::calibrate_population(start, shape, set, fo);
  fit::FitOptions fl = fo;
  fl.starts = 1;
  fl.design_points = o.fold_warm_design_points;
  fit::PopulationFit local = refine_warm(windowed(start, 0.15), shape, set, fl);
  if (local.error < r.fit.error) r.fit = std::move(local);
  r.model = with_values(start, r.fit.params);
  r.law = detail::law_of(r.model, r.fit.params, effects, registry);
  r.error = mean_error(r.fit, set.size());
  return r;
}

}  // namespace

std::vector<Rival> calibrate_rivals(const Model& base, const Shape& shape, const ImpactSet& set,
                                    const std::vector<std::vector<std::string>>& rivals,
                                    const AssessOptions& options, const EffectRegistry& registry) {
  const AssessOptions o = resolve_scale(set, options);
  std::vector<Rival> out(1 + rivals.size());
  // The base model as given: the population fit of assess() (a cold start).
  Rival& b = out[0];
  b.name = "none";
  const Model model = calibration_model_for(base, set, o);
  fit::FitOptions fo = fit_options_for(set, o);
  fo.intervals = false;
  fo.starts = full_set_starts(o, fo.error, shape, set);
  b.fit = fit::calibrate_population(model, shape, set, fo);
  b.model = with_values(model, b.fit.params);
  b.law = detail::law_of(b.model, b.fit.params, b.model.effect_names(), registry);
  b.error = mean_error(b.fit, set.size());

  const std::vector<Rival> rest = calibrate_rivals_from(b, shape, set, rivals, o, registry);
  std::copy(rest.begin(), rest.end(), out.begin() + 1);
  return out;
}

std::vector<RivalCalibration> try_calibrate_rivals_from(
    const Rival& base, const Shape& shape, const ImpactSet& set,
    const std::vector<std::vector<std::string>>& rivals, const AssessOptions& options,
    const EffectRegistry& registry) {
  const AssessOptions o = resolve_scale(set, options);
  std::vector<RivalCalibration> out(rivals.size());
  // One calibration per thread.
  const int available = o.fit.threads > 0 ? o.fit.threads : omp_get_max_threads();
  const int threads = std::max(
      1, std::min<int>(available, static_cast<int>(std::max<std::size_t>(1, rivals.size()))));
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t k = 0; k < rivals.size(); ++k) {
    try {
      out[k].rival = rivals[k].empty() ? base
                                       : calibrate_one(base.model, rivals[k], shape, set, o,
                                                       registry, threads > 1 ? 1 : o.fit.threads);
    } catch (const std::exception& e) {
      out[k].error = e.what();
    }
  }
  return out;
}

std::vector<Rival> calibrate_rivals_from(const Rival& base, const Shape& shape,
                                         const ImpactSet& set,
                                         const std::vector<std::vector<std::string>>& rivals,
                                         const AssessOptions& options,
                                         const EffectRegistry& registry) {
  std::vector<Rival> out;
  const auto each = try_calibrate_rivals_from(base, shape, set, rivals, options, registry);
  for (std::size_t k = 0; k < each.size(); ++k) {
    if (!each[k].rival)
      throw std::runtime_error("rival '" + rival_name(rivals[k]) +
                               "' could not be calibrated: " + each[k].error);
    out.push_back(*each[k].rival);
  }
  return out;
}

std::vector<std::string> default_rivals(const Model& base, const Shape& shape, const ImpactSet& set,
                                        const DiagnoseOptions& options) {
  const Diagnosis d = diagnose(base, shape, set, options);
  // The confidence set (issue 31 item 1), one law per family: its members are ordered best
  // first, so each family's first member is its best. A set can hold all 46 laws (the lab
  // cylinders); the throws are designed to tell the families apart, and the law as it stands
  // ("none", its own family) is always a rival, in the set or not.
  std::vector<std::string> names = {"none"};
  std::vector<Family> seen = {Family::kNone};
  for (const LawMember& m : d.confidence_set.members) {
    if (m.effects.size() != 1) continue;  // a pair is its first effect's family, already in
    if (std::find(seen.begin(), seen.end(), m.family) != seen.end()) continue;
    seen.push_back(m.family);
    names.push_back(m.effect);
  }
  return names;
}

}  // namespace ricochet::diagnosis
