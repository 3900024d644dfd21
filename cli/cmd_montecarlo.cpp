// `ricochet montecarlo --shape S --n N [--range NAME=LO:HI ...] [--vin VX,VY,W | --incident DATA]
// [--compare DATA] [--seed K] --json`: Monte Carlo of the reflected velocities and comparison
// of their CDFs with measurements (paper section 4.3, Figs. 15-16); optionally calibrates the
// uniform ranges against the measured CDFs (docs/commands/montecarlo.md).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/clock.hpp"
#include "common/error.hpp"
#include "fit/fit.hpp"
#include "fit/fit_io.hpp"
#include "model_options.hpp"
#include "shared_options.hpp"
#include "stats/stats.hpp"
#include "uq/figures.hpp"
#include "uq/montecarlo.hpp"
#include "uq/uq_io.hpp"
#include "uq_options.hpp"

namespace ricochet::cli {
namespace {

struct MonteCarloCliOptions {
  ModelOptions model;
  InputOptions inputs;
  OutputOptions output;
  /// --n, --seed and --threads write into mc, --range-runs and --range-evaluations into range:
  /// their defaults are the uq module's, shown by --help.
  uq::MonteCarloOptions mc;
  uq::RangeFitOptions range;
  std::string vin;
  std::vector<double> alpha_range_deg;
  std::string incident, compare, where, fitted, figures, distance = "cvm";
  bool calibrate_ranges = false, resume = false, no_progress = false;
};

// Per calibrated parameter of a calibration file: a distribution fitted to its per-release
// values (OpenTURNS, BIC), truncated to the model's bounds.
std::vector<uq::ParameterInput> fitted_inputs(const std::string& path, const Model& model) {
  const auto fits = fit::read_release_fits(path);
  if (fits.empty()) throw InputError(path, 0, "calibration", "no release in the file");
  std::vector<uq::ParameterInput> out;
  for (std::size_t i : fits.front().calibrated) {
    const std::string& name = fits.front().names[i];
    std::vector<double> v;
    for (const auto& f : fits) v.push_back(f.value(name));
    std::size_t m = 0;
    try {
      m = model.index(name);
    } catch (const std::exception& e) {
      throw InputError(path, 0, "names", e.what());
    }
    try {
      out.push_back({name, uq::Distribution::fitted(v, model.lower(m), model.upper(m))});
    } catch (const std::exception& e) {
      throw InputError(path, 0, name, std::string("cannot fit a distribution: ") + e.what());
    }
  }
  return out;
}

// The inputs' distributions: uniform over --range (paper Table 5), or fitted to a calibration
// file's per-release values (--fitted) with explicit --range overriding them.
std::vector<uq::ParameterInput> build_inputs(const MonteCarloCliOptions& o, const Model& model) {
  if (o.fitted.empty()) return o.inputs.build(model);
  std::vector<uq::ParameterInput> inputs = fitted_inputs(o.fitted, model);
  if (o.inputs.ranges.empty()) return inputs;
  const auto ranged = o.inputs.build(model);
  for (const auto& text : o.inputs.ranges) {
    const auto name = uq::parse_range(text, "--range").first;
    for (const auto& in : ranged)
      if (in.name == name) {
        bool replaced = false;
        for (auto& cur : inputs)
          if (cur.name == name) cur = in, replaced = true;
        if (!replaced) inputs.push_back(in);
      }
  }
  return inputs;
}

// The command line's names of the uq options it binds (their ranges: the options' problems()).
const OptionNames kMonteCarloNames = {{"runs", "--n"},
                                      {"alpha_min_rad", "--alpha-range"},
                                      {"alpha_max_rad", "--alpha-range"},
                                      {"engine.dt_s", "--dt"}};
const OptionNames kRangeFitNames = {{"mc.runs", "--range-runs"},
                                    {"max_evaluations", "--range-evaluations"}};

// The uq module's options with the command line's time step, progress, --vin and --alpha-range,
// refused (exit 2) where the module would refuse them.
uq::MonteCarloOptions mc_options(const MonteCarloCliOptions& o, const std::optional<Vel3>& vin) {
  uq::MonteCarloOptions mc = o.mc;
  mc.engine.dt_s = o.model.engine_options().dt_s;
  mc.progress = !o.no_progress && !o.output.json;
  if (vin) mc.vin = *vin;
  if (!o.alpha_range_deg.empty()) {
    if (o.alpha_range_deg.size() != 2 || !(o.alpha_range_deg[0] < o.alpha_range_deg[1]))
      throw InputError("<command line>", 0, "--alpha-range", "expected LO,HI in degrees, LO < HI");
    refuse_degrees("--alpha-range", o.alpha_range_deg, uq::MonteCarloOptions::kAlphaRad);
    mc.alpha_min_rad = o.alpha_range_deg[0] * M_PI / 180.0;
    mc.alpha_max_rad = o.alpha_range_deg[1] * M_PI / 180.0;
  }
  refuse_problems(mc.problems(), kMonteCarloNames);
  return mc;
}

// The range fit's options (--calibrate-ranges): the Monte Carlo's with the range fit's own runs,
// checked with the others even when the range fit is not asked for.
uq::RangeFitOptions range_fit_options(const MonteCarloCliOptions& o,
                                      const uq::MonteCarloOptions& mc) {
  uq::RangeFitOptions rf = o.range;
  rf.mc = mc;
  rf.mc.runs = o.range.mc.runs;
  rf.mc.progress = false;
  if (o.distance == "ks")
    rf.distance = uq::RangeFitOptions::Distance::kKolmogorovSmirnov;
  else if (o.distance != "cvm")
    throw InputError("<command line>", 0, "--distance", "expected 'cvm' or 'ks'");
  refuse_problems(rf.problems(), kRangeFitNames);
  return rf;
}

// The runs, appended to (and resumed from) the HDF5 store when there is one.
uq::MonteCarloResult run_runs(const Model& model, const Shape& shape,
                              const std::vector<uq::ParameterInput>& inputs,
                              const uq::MonteCarloOptions& mc, uq::MonteCarloStore* store) {
  uq::MonteCarloResult result;
  try {
    result = uq::run_monte_carlo(
        model, shape, inputs, mc,
        [&](std::size_t begin, std::size_t end, const uq::MonteCarloResult& r) {
          if (store) store->append(begin, end, r);
        },
        store ? store->done_runs() : 0);
  } catch (const std::invalid_argument& e) {
    throw InputError("<command line>", 0, "--range", e.what());
  }
  if (store) store->load(result);
  return result;
}

// --calibrate-ranges: the uniform ranges fitted to the measured CDFs, then checked by an
// independent full-size Monte Carlo (new seed), returned; doc["range_fit"] reports both.
std::unique_ptr<uq::MonteCarloResult> calibrate_ranges(
    const MonteCarloCliOptions& o, const Model& model, const Shape& shape,
    const ImpactSet& measured, const std::vector<uq::ParameterInput>& inputs,
    const uq::MonteCarloOptions& mc, const uq::RangeFitOptions& rf, nlohmann::json& doc) {
  const uq::RangeFitResult fitr = uq::calibrate_ranges(model, shape, measured, inputs, rf);
  uq::MonteCarloOptions check = mc;
  check.seed = mc.seed + 1;
  check.progress = false;
  auto calibrated_mc =
      std::make_unique<uq::MonteCarloResult>(uq::run_monte_carlo(model, shape, fitr.ranges, check));
  const uq::CdfComparison c = uq::compare_cdfs(*calibrated_mc, measured);
  doc["range_fit"] = {{"ranges", uq::inputs_json(fitr.ranges)},
                      {"distance", o.distance},
                      {"objective", fitr.distance},
                      {"objective_start", fitr.initial_distance},
                      {"evaluations", fitr.evaluations},
                      {"runs_per_evaluation", rf.mc.runs},
                      {"check_runs", calibrated_mc->size()},
                      {"ks", uq::components_json(c.ks)},
                      {"p_value", uq::components_json(c.p_value)},
                      {"cvm", uq::components_json(c.cvm)},
                      {"seconds", fitr.seconds}};
  return calibrated_mc;
}

void write_figures(const MonteCarloCliOptions& o, const Model& model,
                   const uq::MonteCarloResult& result, const ImpactSet* measured,
                   const uq::MonteCarloResult* calibrated_mc) {
  std::filesystem::create_directories(o.figures);
  std::vector<std::pair<std::string, const uq::MonteCarloResult*>> extra;
  if (calibrated_mc) extra.push_back({"calibrated ranges", calibrated_mc});
  uq::figure_reflected_cdfs(result, measured, o.figures + "/montecarlo_cdf.svg",
                            o.fitted.empty() ? "uniform ranges" : "fitted distributions", extra);
  if (!o.fitted.empty())
    uq::figure_parameter_cdfs(fit::read_release_fits(o.fitted), uq::paper_ranges(model),
                              o.figures + "/montecarlo_parameters_cdf.svg");
}

void print_text(const uq::MonteCarloResult& result, const Shape& shape,
                const std::vector<uq::ParameterInput>& inputs, const nlohmann::json& doc,
                bool compared) {
  std::cout << fmt::format("Monte Carlo: {} runs of shape {} in {:.2f} s ({} failed)\n",
                           result.size(), shape.name, result.seconds,
                           doc["failed_runs"].get<std::size_t>());
  for (const auto& in : inputs)
    std::cout << "  " << in.name << " ~ " << in.distribution.description() << "\n";
  for (int k = 0; k < 3; ++k) {
    const stats::Summary s = stats::summarize(result.component(k));
    std::cout << fmt::format("  {:<3} mean {:8.3f}  std {:7.3f}", kComponentNames[k], s.mean,
                             s.std);
    if (compared)
      std::cout << fmt::format("   KS {:.3f}  p = {:.3g}",
                               doc["ks"][kComponentNames[k]].get<double>(),
                               doc["p_value"][kComponentNames[k]].get<double>());
    std::cout << "\n";
  }
  if (doc.contains("range_fit"))
    std::cout << "Calibrated ranges:\n" << doc["range_fit"].dump(2) << "\n";
}

void run(const MonteCarloCliOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  // --vin is checked before any work, like every option (docs/commands/README.md).
  const std::optional<Vel3> vin = o.vin.empty() ? std::nullopt : std::optional(parse_vin(o.vin));
  const Model model = o.model.build_model();
  const Shape shape = o.model.build_shape();
  if (!o.vin.empty() && !o.incident.empty())
    throw InputError("<command line>", 0, "--vin", "give either --vin or --incident, not both");
  const bool h5 = !o.output.out.empty() && !o.output.out.ends_with(".csv");
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  if (o.resume && !h5)
    throw InputError("<command line>", 0, "--resume", "needs --out FILE.h5 (the file to continue)");
  const std::vector<uq::ParameterInput> inputs = build_inputs(o, model);
  uq::MonteCarloOptions mc = mc_options(o, vin);
  const uq::RangeFitOptions rf = range_fit_options(o, mc);
  ImpactSet incident;
  if (!o.incident.empty()) {
    incident =
        fit::select_shape(filter_nonempty(read_impact_set(o.incident), o.where, o.incident), shape);
    mc.incident = &incident;
  }
  std::unique_ptr<ImpactSet> measured;
  if (!o.compare.empty())
    measured = std::make_unique<ImpactSet>(
        fit::select_shape(filter_nonempty(read_impact_set(o.compare), o.where, o.compare), shape));
  if (o.calibrate_ranges && !measured)
    throw InputError("<command line>", 0, "--calibrate-ranges", "needs --compare DATA");

  std::unique_ptr<uq::MonteCarloStore> store;
  if (h5)
    store = std::make_unique<uq::MonteCarloStore>(o.output.out, model, shape, inputs, mc,
                                                  o.incident, o.resume);
  const uq::MonteCarloResult result = run_runs(model, shape, inputs, mc, store.get());
  nlohmann::json doc;
  doc["runs"] = result.size();
  doc["shape"] = shape.name;
  doc["inputs"] = uq::inputs_json(inputs);
  doc["settings"] = uq::to_json(mc, o.incident);
  doc["model"] = model.to_json();
  std::size_t failed = 0;
  for (int s : result.status) failed += s != 0;
  doc["failed_runs"] = failed;
  doc["reflected"] = uq::moments_json(result);
  if (measured) {
    const uq::CdfComparison c = uq::compare_cdfs(result, *measured);
    doc["ks"] = uq::components_json(c.ks);
    doc["p_value"] = uq::components_json(c.p_value);
    doc["cvm"] = uq::components_json(c.cvm);
    doc["compare"] = {{"data", o.compare}, {"releases", c.n_measured}};
    if (store) store->write_json("comparison", doc);
  }
  std::unique_ptr<uq::MonteCarloResult> calibrated_mc;
  if (o.calibrate_ranges) {
    calibrated_mc = calibrate_ranges(o, model, shape, *measured, inputs, mc, rf, doc);
    if (store) store->write_json("range_fit", doc["range_fit"]);
  }
  if (!o.output.out.empty() && !h5) uq::write_runs_csv(o.output.out, result);
  if (!o.figures.empty()) write_figures(o, model, result, measured.get(), calibrated_mc.get());
  doc["seconds"] = seconds_since(t0);
  doc["simulation_seconds"] = result.seconds;
  if (o.output.json) {
    print_json(doc);
    return;
  }
  print_text(result, shape, inputs, doc, measured != nullptr);
}

}  // namespace

void add_montecarlo_command(CLI::App& app) {
  auto opts = std::make_shared<MonteCarloCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "montecarlo", "Monte Carlo of reflected velocities and CDF comparison (paper section 4.3)");
  add_model_options(sub, opts->model);
  add_output_options(sub, opts->output);
  add_input_options(sub, opts->inputs);
  sub->add_option("--n", opts->mc.runs, "Number of runs")->capture_default_str();
  show_range(sub, "--n", uq::MonteCarloOptions::kRuns);
  add_seed_option(sub, opts->mc.seed, "the runs' random numbers");
  add_vin_option(sub, opts->vin,
                 "Fixed incident state (default " + format_vin(uq::MonteCarloOptions{}.vin) + ")");
  sub->add_option("--incident", opts->incident, "Resample incident states from this impact set");
  sub->add_option(
         "--alpha-range", opts->alpha_range_deg,
         fmt::format("Orientation range of non-disc blocks LO,HI [deg] (default "
                     "{:g},{:g})",
                     opts->mc.alpha_min_rad * 180 / M_PI, opts->mc.alpha_max_rad * 180 / M_PI))
      ->delimiter(',');
  sub->add_option("--compare", opts->compare, "Measured impact set: KS per component");
  add_where_option(sub, opts->where, "the releases of --incident and --compare");
  sub->add_option("--fitted", opts->fitted,
                  "Calibration file (ricochet calibrate --out X.h5): vary each calibrated "
                  "parameter by a distribution fitted to its per-release values");
  sub->add_flag("--calibrate-ranges", opts->calibrate_ranges,
                "Fit the uniform ranges to the --compare CDFs (common random numbers)");
  sub->add_option("--range-runs", opts->range.mc.runs, "Runs per evaluation of the range fit")
      ->capture_default_str();
  sub->add_option("--range-evaluations", opts->range.max_evaluations,
                  "Objective evaluations of the range fit")
      ->capture_default_str();
  sub->add_option("--distance", opts->distance, "Range-fit distance: cvm or ks")
      ->capture_default_str();
  add_threads_option(sub, opts->mc.engine.threads);
  sub->add_flag("--resume", opts->resume, "Continue the run stored in --out FILE.h5");
  sub->add_flag("--no-progress", opts->no_progress, "No progress bar");
  add_figures_option(sub, opts->figures);
  show_range(sub, "--alpha-range", degrees(uq::MonteCarloOptions::kAlphaRad));
  show_range(sub, "--range-runs", uq::MonteCarloOptions::kRuns);
  show_range(sub, "--range-evaluations", uq::RangeFitOptions::kMaxEvaluations);
  sub->callback([opts] { run(*opts); });
}

}  // namespace ricochet::cli
