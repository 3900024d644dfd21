// `ricochet calibrate DATA --shape S [--model FILE] [--seed K] [--starts N] --json`: per-release
// calibration of paper Eq. 7 with identifiability intervals, and optionally one population fit
// (docs/commands/calibrate.md). When every release has penetration and/or contact duration,
// those terms join Eq. 7 and kn is calibrated too (fit::with_contact_terms,
// fit::calibration_model: the diagnosis's rule); --no-features keeps Eq. 7 and kn fixed.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/clock.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "fit/fit.hpp"
#include "fit/fit_io.hpp"
#include "model_options.hpp"
#include "shared_options.hpp"
#include "uq/distribution.hpp"
#include "uq/figures.hpp"

namespace ricochet::cli {
namespace {

struct CalibrateOptions {
  /// The options bound to fit settings write straight into `fit`: their defaults are the fit
  /// module's (fit::FitOptions), shown by --help.
  fit::FitOptions fit;
  std::string data, where, figures, alpha_mode = fit::alpha_mode_name(fit::FitOptions{}.alpha.mode);
  ModelOptions model;
  OutputOptions output;
  std::vector<double> sigma, alpha_range_deg;
  bool no_intervals = !fit::FitOptions{}.intervals, population = false, resume = false,
       no_features = false;
};

Vel3 parse_sigma(const std::vector<double>& v) {
  if (v.size() != 3)
    throw InputError("<command line>", 0, "--sigma",
                     "expected three values SX,SY,SW (m/s, m/s, rad/s)");
  return {v[0], v[1], v[2]};
}

// The command line's names of the fit settings it binds (their ranges: FitOptions::problems).
const OptionNames kFitNames = {{"starts", "--starts"},
                               {"design_points", "--design-points"},
                               {"sigma", "--sigma"},
                               {"threshold_scale", "--threshold-scale"},
                               {"engine.dt_s", "--dt"},
                               {"alpha.min_rad", "--alpha-range"},
                               {"alpha.max_rad", "--alpha-range"}};

fit::FitOptions fit_options(const CalibrateOptions& o) {
  fit::FitOptions f = o.fit;
  f.engine.dt_s = o.model.engine_options().dt_s;
  f.intervals = !o.no_intervals;
  if (!o.sigma.empty()) f.sigma = parse_sigma(o.sigma);
  if (o.alpha_mode == "fit")
    f.alpha.mode = fit::AlphaMode::kFit;
  else if (o.alpha_mode == "marginal")
    f.alpha.mode = fit::AlphaMode::kMarginal;
  else
    throw InputError("<command line>", 0, "--alpha", "expected 'fit' or 'marginal'");
  if (!o.alpha_range_deg.empty()) {
    if (o.alpha_range_deg.size() != 2 || !(o.alpha_range_deg[0] < o.alpha_range_deg[1]))
      throw InputError("<command line>", 0, "--alpha-range", "expected LO,HI in degrees, LO < HI");
    refuse_degrees("--alpha-range", o.alpha_range_deg, fit::FitOptions::kAlphaRad);
    f.alpha.min_rad = o.alpha_range_deg[0] * M_PI / 180.0;
    f.alpha.max_rad = o.alpha_range_deg[1] * M_PI / 180.0;
  }
  refuse_problems(f.problems(), kFitNames);
  return f;
}

std::string value_text(const fit::ReleaseFit& f, std::size_t i) {
  const std::string& name = f.names[i];
  const fit::ParameterInterval* iv = f.interval(name);
  // A value printed alone only where it is identified; otherwise the verdict.
  if (!iv) return fmt::format("{} = {:.3g}", name, f.params[i]);
  if (iv->status == fit::Identifiability::kIdentified)
    return fmt::format("{} = {:.3g} [{:.3g}, {:.3g}]", name, f.params[i], iv->lo, iv->hi);
  return iv->statement;
}

void print_text(const std::vector<fit::ReleaseFit>& fits, const nlohmann::json& summary,
                const fit::PopulationFit* pop, const std::string& shape, double seconds) {
  std::cout << fmt::format("Calibration of paper Eq. 7, {} releases of shape {} ({:.2f} s)\n",
                           fits.size(), shape, seconds);
  for (const auto& f : fits) {
    std::cout << fmt::format("{:<6} Eq.7 = {:.4f} (threshold {:.4f})", f.id, f.error, f.threshold);
    if (f.alpha_source == "fitted" || f.alpha_source == "data")
      std::cout << fmt::format("  alpha_in = {:.1f} deg ({})", f.alpha_rad * 180.0 / M_PI,
                               f.alpha_source);
    std::cout << "\n";
    for (std::size_t i : f.calibrated) std::cout << "       " << value_text(f, i) << "\n";
  }
  std::cout << "Summary over releases (mean +- std of the optimiser's values; only meaningful "
               "where identified):\n";
  for (auto it = summary.begin(); it != summary.end(); ++it) {
    const auto& s = it.value();
    if (!s.contains("mean") || s["mean"].is_null()) continue;
    std::cout << fmt::format("  {:<8} {:.3f} +- {:.3f}", it.key(), s["mean"].get<double>(),
                             s["std"].is_null() ? NAN : s["std"].get<double>());
    if (s.contains("counts"))
      std::cout << fmt::format(
          "   identified in {}/{} releases, lower bound only {}, upper "
          "bound only {}, not identified {}",
          s["counts"]["identified"].get<int>(), s["n"].get<int>(),
          s["counts"]["lower_bound_only"].get<int>(), s["counts"]["upper_bound_only"].get<int>(),
          s["counts"]["not_identified"].get<int>());
    std::cout << "\n";
  }
  if (pop) {
    std::cout << fmt::format("Population fit: summed Eq. 7 = {:.3f} (mean {:.4f} per release)\n",
                             pop->error,
                             pop->error / static_cast<double>(pop->release_errors.size()));
    for (std::size_t k = 0; k < pop->calibrated.size(); ++k) {
      const std::size_t i = pop->calibrated[k];
      std::cout << "  "
                << (k < pop->intervals.size()
                        ? pop->intervals[k].statement
                        : fmt::format("{} = {:.3g}", pop->names[i], pop->params[i]))
                << "\n";
    }
  }
}

// Per-release fits, appended to (and resumed from) the HDF5 store when there is one, with a
// progress bar; the fits already in the store replace their releases' placeholders.
std::vector<fit::ReleaseFit> calibrate_each_release(const Model& model, const Shape& shape,
                                                    const ImpactSet& set,
                                                    const fit::FitOptions& options,
                                                    fit::ReleaseFitStore* store) {
  std::vector<fit::ReleaseFit> fits;
  {
    Progress bar("calibrate", set.size());
    fit::ReleaseHooks hooks;
    if (store) {
      hooks.already_done = [&](std::size_t i) { return store->done(set.impacts[i].id); };
      for (std::size_t i = 0; i < set.size(); ++i)
        if (store->done(set.impacts[i].id)) bar.advance();
    }
    hooks.on_done = [&](std::size_t i, const fit::ReleaseFit& f) {
      if (store) store->append(i, f);
      bar.status(f.id);
      bar.advance();
    };
    fits = fit::calibrate_releases(model, shape, set, options, hooks);
    bar.finish();
  }
  if (store)
    for (const auto& f : store->existing())
      for (std::size_t i = 0; i < set.size(); ++i)
        if (set.impacts[i].id == f.id) fits[i] = f;
  return fits;
}

nlohmann::json result_json(const CalibrateOptions& o, const std::vector<fit::ReleaseFit>& fits,
                           const nlohmann::json& summary, const fit::PopulationFit* pop,
                           const Model& model, const Shape& shape, const fit::FitOptions& options,
                           double seconds) {
  nlohmann::json doc;
  doc["releases"] = nlohmann::json::array();
  for (const auto& f : fits) doc["releases"].push_back(fit::to_json(f));
  doc["summary"] = summary;
  doc["seconds"] = seconds;
  doc["shape"] = shape.name;
  doc["data"] = o.data;
  doc["model"] = model.to_json();
  doc["settings"] = fit::to_json(options);
  doc["equation"] =
      std::string("Eq. 7: sum over vx, vy, w of ((V_sim - V_meas) / max(|V_meas|, floor))^2") +
      (options.error.penetration ? " + ((h_sim - h_meas) / penetration_scale_m)^2" : "") +
      (options.error.contact_duration ? " + ((T_sim - T_meas) / contact_duration_scale_s)^2" : "");
  doc["threshold_definition"] =
      "near-optimal: Eq. 7 <= optimum + threshold_scale * sum_k (sigma_k / max(|V_meas_k|, "
      "floor_k))^2, plus (sigma_h / d_h)^2 and (sigma_T / d_T)^2 for the contact terms";
  if (!shape.is_disc())
    doc["alpha_in"] = {
        {"mode", fit::alpha_mode_name(options.alpha.mode)},
        {"range_deg", {options.alpha.min_rad * 180 / M_PI, options.alpha.max_rad * 180 / M_PI}},
        {"note",
         options.alpha.mode == fit::AlphaMode::kFit
             ? "releases without a measured alpha_in: fitted per release as a nuisance "
               "parameter (periodic range)"
             : "releases without a measured alpha_in: Eq. 7 averaged over the orientations"}};
  if (pop) doc["population"] = fit::to_json(*pop);
  return doc;
}

void run(const CalibrateOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const bool h5 = !o.output.out.empty() && !o.output.out.ends_with(".csv");
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  if (o.resume && !h5)
    throw InputError("<command line>", 0, "--resume", "needs --out FILE.h5 (the file to continue)");
  const Model given = o.model.build_model();
  const Shape shape = o.model.build_shape();
  fit::FitOptions options = fit_options(o);
  const ImpactSet set =
      fit::select_shape(filter_nonempty(read_impact_set(o.data), o.where, o.data), shape);
  // The set's contact features enter the error, and then kn is calibrated: the same rule as
  // compare, diagnose and ladder (fit/fit.hpp).
  if (!o.no_features) options.error = fit::with_contact_terms(options.error, set);
  const Model model = fit::calibration_model(given, options.error);

  std::unique_ptr<fit::ReleaseFitStore> store;
  if (h5)
    store =
        std::make_unique<fit::ReleaseFitStore>(o.output.out, model, shape, set, options, o.resume);
  const std::vector<fit::ReleaseFit> fits =
      calibrate_each_release(model, shape, set, options, store.get());
  std::unique_ptr<fit::PopulationFit> pop;
  if (o.population)
    pop =
        std::make_unique<fit::PopulationFit>(fit::calibrate_population(model, shape, set, options));
  const double seconds = seconds_since(t0);
  const nlohmann::json summary = fit::summary_json(fits);
  if (store) store->write_summary(fits, pop.get(), seconds);
  if (!o.output.out.empty() && !h5) fit::write_csv(o.output.out, fits);
  if (!o.figures.empty()) {
    std::filesystem::create_directories(o.figures);
    uq::figure_parameter_cdfs(fits, uq::paper_ranges(model),
                              o.figures + "/calibrate_parameters_cdf.svg");
    if (options.intervals) uq::figure_intervals(fits, o.figures + "/calibrate_intervals.svg");
    uq::figure_fit_quality(fits, o.figures + "/calibrate_fit.svg");
  }
  if (o.output.json)
    print_json(result_json(o, fits, summary, pop.get(), model, shape, options, seconds));
  else
    print_text(fits, summary, pop.get(), shape.name, seconds);
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  auto opts = std::make_shared<CalibrateOptions>();
  CLI::App* sub = app.add_subcommand(
      "calibrate",
      "Calibrate the model per release (paper Eq. 7, Table 4) with identifiability intervals");
  sub->add_option("DATA", opts->data, "Impact set (.csv or .h5)")->required();
  add_model_options(sub, opts->model);
  add_output_options(sub, opts->output);
  const fit::FitOptions defaults;
  add_where_option(sub, opts->where, "the releases of DATA");
  add_seed_option(sub, opts->fit.seed, "the start design");
  sub->add_option("--starts", opts->fit.starts, "BOBYQA runs per release")->capture_default_str();
  sub->add_option("--design-points", opts->fit.design_points,
                  "Start design size besides the model's values (0 = 16 per fitted variable; "
                  "-1 = none: a local refinement from the model's values)")
      ->capture_default_str();
  sub->add_option("--sigma", opts->sigma,
                  fmt::format("Measurement uncertainty of V_out SX,SY,SW (m/s, m/s, rad/s) for "
                              "the identifiability threshold; default {:g},{:g},{:g} (paper "
                              "Table 1)",
                              defaults.sigma[0], defaults.sigma[1], defaults.sigma[2]))
      ->delimiter(',');
  sub->add_option("--threshold-scale", opts->fit.threshold_scale,
                  "Multiply the near-optimal threshold (e.g. 4 for two sigma)")
      ->capture_default_str();
  sub->add_flag("--no-intervals", opts->no_intervals, "Skip the identifiability intervals");
  sub->add_flag("--no-features", opts->no_features,
                "Ignore penetration and contact duration even when the data have them (Eq. 7 "
                "alone; kn stays fixed)");
  sub->add_option("--alpha", opts->alpha_mode,
                  "Unknown alpha_in of non-disc blocks: fit (nuisance) or marginal")
      ->capture_default_str();
  sub->add_option(
         "--alpha-range", opts->alpha_range_deg,
         fmt::format("Range of alpha_in LO,HI [deg], one symmetry period (default "
                     "{:g},{:g})",
                     defaults.alpha.min_rad * 180 / M_PI, defaults.alpha.max_rad * 180 / M_PI))
      ->delimiter(',');
  sub->add_flag("--population", opts->population, "Also fit one parameter set to all releases");
  add_threads_option(sub, opts->fit.threads);
  sub->add_flag("--resume", opts->resume, "Continue the run stored in --out FILE.h5");
  add_figures_option(sub, opts->figures);
  show_range(sub, "--starts", fit::FitOptions::kStarts);
  show_range(sub, "--design-points", fit::FitOptions::kDesignPoints);
  show_range(sub, "--sigma", fit::FitOptions::kSigma);
  show_range(sub, "--threshold-scale", fit::FitOptions::kThresholdScale);
  show_range(sub, "--alpha-range", degrees(fit::FitOptions::kAlphaRad));
  sub->callback([opts] { run(*opts); });
}

}  // namespace ricochet::cli
