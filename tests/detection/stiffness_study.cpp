// `stiffness_study`: which contact stiffnesses (kn, kt, kr) rebound velocities plus the contact
// features (maximum penetration, contact duration) identify (issue 11, item 5;
// docs/diagnosis.md, "Which stiffnesses the contact features identify").
//
// Data: sets of the independent simulator (truth_sim.hpp: another integrator, dt = 2e-6 s,
// kn = kt = 3e7 N/m, kr = 5e7 N m/rad, lever arm R - h, its own end of contact), with
// release-to-release scatter of e_n^2, mu, mu_R and lab-like noise on V_in, V_out (0.05 m/s,
// 0.03 m/s, 2 rad/s), penetration (0.5 mm) and duration (1 ms). The engine's model is the
// paper's law at its nominal values (kn = kt = 1e7 N/m, kr = 1e8 N m/rad).
// Fits (fit/fit.hpp, through the fit module only), for each seed:
//   kn          the model as the fit calibrates it on these data (fit::calibration_model:
//               e_n^2, mu, mu_R, kn), population fit with near-optimal intervals;
//   kn, kt, kr  the same with kt and kr calibrated too (within their declared bounds, kr's
//               capped at 1e9 N m/rad by the engine's stability at dt = 1e-5 s);
//   releases    per-release fits of kn, kt, kr (with e_n^2, mu, mu_R) on the first
//               `--releases` releases: how often each stiffness is identified.
// Output: one JSON line per seed, then a summary table on stderr.
//
//   stiffness_study [--seeds 5] [--n 40] [--releases 8] [--resolution 0.0025]
//                   [--noise-penetration 5e-4] [--noise-duration 1e-3]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "diagnosis/assess.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "fit/fit.hpp"
#include "truth_sim.hpp"

using namespace ricochet;

namespace {

nlohmann::json interval_json(const fit::ParameterInterval& iv) {
  return {{"value", iv.value},
          {"lo", iv.lo},
          {"hi", iv.hi},
          {"status", fit::identifiability_name(iv.status)}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Identifiability of kn, kt, kr from V_out, penetration and contact duration"};
  int seeds = 5, releases = 8;
  long long n = 40;
  double resolution = 0.0025;
  app.add_option("--seeds", seeds, "Sets (seeds 1..N)")->check(CLI::Range(1, 100));
  app.add_option("--n", n, "Releases per set")->check(CLI::Range(4, 1000));
  app.add_option("--releases", releases, "Per-release fits per set")->check(CLI::Range(0, 1000));
  app.add_option("--resolution", resolution, "Interval resolution (fraction of the unit box)")
      ->check(CLI::Range(1e-4, 0.1));
  double noise_h = truth::SetOptions{}.noise_penetration_m;
  double noise_t = truth::SetOptions{}.noise_contact_duration_s;
  app.add_option("--noise-penetration", noise_h, "Penetration noise sd [m]")
      ->check(CLI::Range(0.0, 0.01));
  app.add_option("--noise-duration", noise_t, "Contact duration noise sd [s]")
      ->check(CLI::Range(0.0, 0.01));
  bool per_release_scale = false;
  app.add_flag("--per-release-feature-scale", per_release_scale,
               "Contact terms divided by max(measured, set mean) release by release (the rule "
               "before fit::ErrorOptions::penetration_scale_m; biased) instead of one constant "
               "per feature, the set's mean measured value");
  CLI11_PARSE(app, argc, argv);

  truth::SetOptions so;
  so.n = static_cast<std::size_t>(n);
  so.refit = false;
  so.contact_features = true;
  so.noise_penetration_m = noise_h;
  so.noise_contact_duration_s = noise_t;
  so.lab_vin =
      truth::lab_cylinder_states(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
  const Shape shape = Shape::resolve("cylinder");
  const Model paper = Model::paper();
  Model all = paper;
  for (const char* k : {"kn", "kt", "kr"}) all.set_calibrated(k, true);
  // kr's declared upper bound (1e10 N m/rad) is beyond the engine's stability limit at the
  // default 1e-5 s step for the lab cylinder (2 / sqrt(kr / I) >= dt: kr <= 1.8e9 N m/rad).
  all.set_bounds("kr", 1e5, 1e9);

  // status counts per parameter over the per-release fits
  std::map<std::string, std::map<std::string, int>> counts;
  for (int seed = 1; seed <= seeds; ++seed) {
    so.seed = static_cast<std::uint64_t>(seed);
    const ImpactSet set = truth::make_set(so).set;
    // The diagnosis's fit options on this set (compare, diagnose, ladder): the contact terms
    // with one constant denominator per feature (the set's mean measured value,
    // fit::with_contact_terms), and every velocity floor raised to the set's mean magnitude
    // (ErrorScale::kSetMean).
    fit::FitOptions fo =
        diagnosis::fit_options_for(set, diagnosis::resolve_scale(set, diagnosis::AssessOptions{}));
    fo.interval_resolution = resolution;
    // The old rule: d_h = max(h_meas, set mean) per release (floors raised by kSetMean).
    const auto old_rule = [&](fit::ErrorOptions& e) {
      if (per_release_scale) e.penetration_scale_m = e.contact_duration_scale_s = 0;
    };
    old_rule(fo.error);
    fo.threads = 0;
    nlohmann::json line = {{"seed", seed}, {"n", set.size()}};
    const Model kn_model = fit::calibration_model(paper, fo.error);
    const fit::PopulationFit pk = fit::calibrate_population(kn_model, shape, set, fo);
    for (const auto& iv : pk.intervals) line["kn_fit"][iv.name] = interval_json(iv);
    line["kn_fit"]["error"] = pk.error;
    line["kn_fit"]["threshold"] = pk.threshold;
    const fit::PopulationFit pa = fit::calibrate_population(all, shape, set, fo);
    for (const auto& iv : pa.intervals) line["all_fit"][iv.name] = interval_json(iv);
    line["all_fit"]["error"] = pa.error;
    line["all_fit"]["threshold"] = pa.threshold;
    ImpactSet first = set;
    first.impacts.resize(std::min<std::size_t>(set.size(), static_cast<std::size_t>(releases)));
    if (!first.impacts.empty()) {
      fit::FitOptions fr = fo;
      fr.error = fit::with_contact_terms(fo.error, first);
      old_rule(fr.error);
      for (const auto& rf : fit::calibrate_releases(all, shape, first, fr))
        for (const auto& iv : rf.intervals) {
          ++counts[iv.name][fit::identifiability_name(iv.status)];
          line["releases"][rf.id][iv.name] = interval_json(iv);
        }
    }
    std::cout << line.dump() << std::endl;
    const auto iv = [](const fit::PopulationFit& f, const char* name) {
      for (const auto& i : f.intervals)
        if (i.name == name) return i;
      return fit::ParameterInterval{};
    };
    const auto show = [](const fit::ParameterInterval& i) {
      std::fprintf(stderr, " %s %.4g [%.4g, %.4g] %s", i.name.c_str(), i.value, i.lo, i.hi,
                   fit::identifiability_name(i.status));
    };
    std::fprintf(stderr, "seed %d: kn fit:", seed);
    show(iv(pk, "kn"));
    std::fprintf(stderr, " | kn, kt, kr fit:");
    for (const char* k : {"kn", "kt", "kr"}) show(iv(pa, k));
    std::fprintf(stderr, "\n");
  }
  for (const auto& [name, c] : counts) {
    std::fprintf(stderr, "per-release %s:", name.c_str());
    for (const auto& [status, k] : c) std::fprintf(stderr, " %s %d", status.c_str(), k);
    std::fprintf(stderr, "\n");
  }
  return 0;
}
