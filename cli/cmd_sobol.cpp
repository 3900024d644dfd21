// `ricochet sobol --shape S --n N [--range NAME=LO:HI ...] --json`: first, second and total
// Sobol indices of the varied parameters on vx, vy, w of V_out, with bootstrap intervals
// (OpenTURNS; paper section 4.4, Appendix B; docs/commands/sobol.md).
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "model_options.hpp"
#include "shared_options.hpp"
#include "uq/figures.hpp"
#include "uq/montecarlo.hpp"
#include "uq/sobol.hpp"
#include "uq/uq_io.hpp"
#include "uq_options.hpp"

namespace ricochet::cli {
namespace {

// The Monte Carlo's fixed incident state (the lab mean, uq::kPaperVin) and engine settings: both
// explore the model around the same collision.
const Vel3 kDefaultVin = uq::MonteCarloOptions{}.vin;
const EngineOptions kEngine = uq::MonteCarloOptions{}.engine;

struct SobolCliOptions {
  ModelOptions model;
  InputOptions inputs;
  OutputOptions output;
  /// --n, --seed, --bootstrap and --confidence write into sobol, --threads into engine: their
  /// defaults are the uq module's, shown by --help.
  uq::SobolOptions sobol;
  EngineOptions engine = kEngine;
  double alpha_deg = 0.0;
  std::string vin;
  std::string estimator = uq::estimator_name(uq::SobolOptions{}.estimator), figures;
};

void print_text(const uq::SobolResult& r) {
  std::cout << fmt::format(
      "Sobol indices ({} estimator, N = {}, {} runs, {:.0f}% bootstrap intervals)\n", r.estimator,
      r.base_size, r.evaluations, 100 * r.confidence);
  for (std::size_t o = 0; o < r.outputs.size(); ++o) {
    std::cout << "output " << r.outputs[o] << fmt::format(" (variance {:.4g})\n", r.variance[o]);
    for (std::size_t i = 0; i < r.inputs.size(); ++i)
      std::cout << fmt::format(
          "  {:<8} first {:7.3f} [{:7.3f}, {:7.3f}]   total {:7.3f} [{:7.3f}, "
          "{:7.3f}]\n",
          r.inputs[i], r.first[o][i].value, r.first[o][i].lo, r.first[o][i].hi, r.total[o][i].value,
          r.total[o][i].lo, r.total[o][i].hi);
    for (std::size_t i = 0; i < r.inputs.size(); ++i)
      for (std::size_t j = i + 1; j < r.inputs.size(); ++j)
        std::cout << fmt::format("  {:<17} second {:7.3f} [{:7.3f}, {:7.3f}]\n",
                                 r.inputs[i] + "-" + r.inputs[j], r.second[o][i][j].value,
                                 r.second[o][i][j].lo, r.second[o][i][j].hi);
  }
  std::cout << "Negative values are estimation noise around zero, reported as estimated.\n";
}

void run(const SobolCliOptions& o) {
  const Vel3 vin = o.vin.empty() ? kDefaultVin : parse_vin(o.vin);
  uq::SobolOptions so = o.sobol;
  try {
    so.estimator = uq::parse_estimator(o.estimator);
  } catch (const std::exception& e) {
    throw InputError("<command line>", 0, "--estimator", e.what());
  }
  refuse_problems(
      so.problems(),
      {{"base_size", "--n"}, {"bootstrap", "--bootstrap"}, {"confidence", "--confidence"}});
  EngineOptions engine = o.engine;
  engine.dt_s = o.model.engine_options().dt_s;
  require_out_extension(o.output, {".h5", ".hdf5"});
  const Model model = o.model.build_model();
  const Shape shape = o.model.build_shape();
  const std::vector<uq::ParameterInput> inputs = o.inputs.build(model);
  if (inputs.size() < 2)
    throw InputError("<command line>", 0, "--range",
                     "Sobol indices need at least two varied parameters");
  const uq::SobolResult r =
      uq::collision_sobol(model, shape, inputs, vin, o.alpha_deg * M_PI / 180.0, so, engine);
  nlohmann::json settings = {{"base_size", so.base_size}, {"seed", so.seed},
                             {"bootstrap", so.bootstrap}, {"confidence", so.confidence},
                             {"estimator", o.estimator},  {"vin", {vin[0], vin[1], vin[2]}},
                             {"alpha_deg", o.alpha_deg},  {"dt_s", engine.dt_s}};
  if (!o.output.out.empty()) uq::write_sobol_h5(o.output.out, r, model, shape, inputs, settings);
  if (!o.figures.empty()) {
    std::filesystem::create_directories(o.figures);
    uq::figure_sobol(r, o.figures + "/sobol.svg");
  }
  if (o.output.json) {
    nlohmann::json doc = uq::to_json(r);
    doc["inputs"] = uq::inputs_json(inputs);
    doc["settings"] = settings;
    doc["shape"] = shape.name;
    doc["model"] = model.to_json();
    print_json(doc);
  } else {
    print_text(r);
  }
}

}  // namespace

void add_sobol_command(CLI::App& app) {
  auto opts = std::make_shared<SobolCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "sobol", "Sobol sensitivity indices of V_out to the model parameters (paper section 4.4)");
  add_model_options(sub, opts->model);
  add_output_options(sub, opts->output);
  add_input_options(sub, opts->inputs);
  sub->add_option("--n", opts->sobol.base_size, "Base sample size N (N (2d + 2) runs)")
      ->capture_default_str();
  add_seed_option(sub, opts->sobol.seed, "the sample designs");
  sub->add_option("--estimator", opts->estimator, "saltelli, jansen, martinez or mauntz-kucherenko")
      ->capture_default_str();
  sub->add_option("--bootstrap", opts->sobol.bootstrap, "Bootstrap resamples")
      ->capture_default_str();
  sub->add_option("--confidence", opts->sobol.confidence, "Interval level")->capture_default_str();
  add_vin_option(sub, opts->vin, "Incident state (default " + format_vin(kDefaultVin) + ")");
  sub->add_option("--alpha", opts->alpha_deg, "Orientation of non-disc blocks [deg]");
  add_threads_option(sub, opts->engine.threads);
  add_figures_option(sub, opts->figures);
  show_range(sub, "--n", uq::SobolOptions::kBaseSize);
  show_range(sub, "--bootstrap", uq::SobolOptions::kBootstrap);
  show_range(sub, "--confidence", uq::SobolOptions::kConfidence);
  check_range(sub, "--alpha", -360, 360);
  sub->callback([opts] { run(*opts); });
}

}  // namespace ricochet::cli
