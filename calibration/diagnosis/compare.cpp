// compare(): the base model calibrated and judged on a set (diagnose.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "common/clock.hpp"
#include "common/progress.hpp"
#include "diagnosis/diagnose.hpp"
#include "engine/engine.hpp"

namespace ricochet::diagnosis {
namespace {

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
  const std::vector<double> floor_h = floor_on_heldout_scale(a, f);
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
      fl.push_back(floor_h[i]);
    }
    r.heldout = mean_se(e);
    r.floor = mean_se(fl);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace

Model with_values(const Model& model, const std::vector<double>& values) {
  Model m = model;
  m.set_values(values);
  return m;
}

DiagnoseOptions resolve_scale(const ImpactSet& set, const DiagnoseOptions& options) {
  DiagnoseOptions o = options;
  o.assess = resolve_scale(set, options.assess);
  return o;
}

Baseline compare(const Model& model_in, const Shape& shape, const ImpactSet& set,
                 const DiagnoseOptions& options, const Assessment* previous) {
  require_valid(options.problems(), "diagnosis::compare");
  const DiagnoseOptions o = resolve_scale(set, options);
  // kn calibrated too when the set's contact features enter the error (assess.hpp).
  const Model model = calibration_model_for(model_in, set, o.assess);
  const auto t0 = std::chrono::steady_clock::now();
  const std::uint64_t c0 = collisions_simulated();
  Baseline b;
  {
    // The base model's fits are most of a compare's time (a lab-triangle set: 11 fits, 26 s).
    Progress bar("compare", 1 + o.assess.repeats * o.assess.folds_for(set.size()), o.progress);
    AssessOptions ao = o.assess;
    ao.progress = &bar;
    b.base = assess(model, shape, set, ao, previous);
    bar.finish();
  }
  const auto& ef = o.assess.fit.error;
  b.error_floors = {
      ef.floor[0], ef.floor[1], ef.floor[2],
      ef.penetration_scale_m > 0 ? ef.penetration_scale_m : ef.penetration_floor_m,
      ef.contact_duration_scale_s > 0 ? ef.contact_duration_scale_s : ef.contact_duration_floor_s};
  const Model warm = with_values(model, b.base.population.params);
  b.floor = noise_floor(warm, shape, b.base.population.params, set, b.base.use, o.assess);
  b.adequacy = adequacy(b.base, b.floor);
  std::vector<double> alpha;
  // A base with nothing calibrated (a law fixed elsewhere, model file `calibrate = []`) has no
  // per-release parameters to drift: its release fits are skipped, not an error.
  if (o.assess.release_fits &&
      !fit::calibration_model(model, o.assess.fit.error).calibrated_indices().empty()) {
    fit::FitOptions fo = fit_options_for(set, o.assess);
    fo.intervals = o.assess.release_intervals;
    b.release_fits = fit::calibrate_releases(warm, shape, set, fo);
    for (const auto& f : b.release_fits) alpha.push_back(f.alpha_rad);
  }
  b.features = impact_features(set, b.base.insample_predictions, alpha);
  b.residual_trends = residual_trends(b.base.heldout, b.base.use, b.features, o.trends);
  b.parameter_trends = parameter_trends(b.release_fits, b.features, o.trends);
  // One family: every residual and parameter trend (about 40 tests).
  control_family({&b.residual_trends, &b.parameter_trends}, o.trends.alpha);
  b.scatter = population_scatter(warm, shape, set, b.base, b.floor, o.assess);
  // Without replicates or declared uncertainties the measurement floor is the fitted one.
  b.floor = b.scatter.measurement;
  b.adequacy = adequacy(b.base, b.floor);
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
  b.collisions = collisions_simulated() - c0;
  return b;
}

}  // namespace ricochet::diagnosis
