// `ricochet diagnose DATA --shape S [--model FILE] --json`: which effect of the catalog is the
// model missing? Ranks every registered effect not in the model by its held-out error after
// recalibration (docs/commands/diagnose.md).
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "diagnosis/figures.hpp"
#include "diagnosis/force_history.hpp"
#include "diagnosis/force_residual.hpp"
#include "diagnosis/inputs.hpp"
#include "diagnosis_options.hpp"
#include "impact/block_track.hpp"
#include "model_options.hpp"

namespace ricochet::cli {
namespace {

[[noreturn]] void no_histories(const std::string& data) {
  throw InputError("<command line>", 0, "--write-force-model",
                   data +
                       " keeps no contact histories of two releases or more (a campaign file's "
                       "/dem/tracks): there is no force law to write");
}

void print_diagnosis(const diagnosis::Diagnosis& d, const std::string& data,
                     const diagnosis::Inputs& in) {
  const auto& b = d.baseline;
  std::cout << fmt::format("{} ({} releases of shape {}), model: ", data, in.set.size(),
                           in.shape.name);
  for (const auto& e : b.base.effects) std::cout << e << " ";
  std::cout << fmt::format("\nnoise floor {:.4g} ({}: {})\n", b.floor.value.mean, b.floor.source,
                           b.floor.description);
  std::cout << fmt::format(
      "base model: in-sample error {:.4g}, held-out error {:.4g} +- {:.2g} "
      "({}-fold)\n",
      b.base.insample.error.mean, b.base.heldout.error.mean, b.base.heldout.error.se, b.base.folds);
  std::cout << "verdict: " << d.verdict << "\n" << d.summary << "\n\n";
  std::cout << fmt::format("{:<5}{:<36}{:>10}{:>10}{:>9}{:>7}{:>9}{:>9}\n", "rank", "effect",
                           "held-out", "drop", "+-SE", "T", "score p", "Holm p");
  for (std::size_t i = 0; i < d.ranking.size(); ++i) {
    const auto& c = d.ranking[i];
    std::cout << fmt::format("{:<5}{:<36}{:>10.4g}{:>10.3g}{:>9.2g}{:>7.2f}{:>9.2g}{:>9.2g}{}\n",
                             i + 1, c.effect, c.heldout_error, c.error_drop, c.drop_se, c.t,
                             c.p_adjusted, c.p_holm, c.supported ? "  supported" : "");
    if (c.supported && !c.law.empty()) std::cout << "     law: " << c.law << "\n";
  }
  if (!d.screened_out.empty())
    std::cout << fmt::format(
        "(score p: the score test, step-down max-T adjusted; Holm p: the held-out drop's "
        "corrected t-test, Holm-adjusted; supported when either is below alpha / 2 and the "
        "held-out error falls. {} candidates tested by the score test only; they count in the "
        "family of {})\n",
        d.screened_out.size(), d.family_size);
  std::cout << "\nevidence:\n";
  for (const auto& c : d.ranking) std::cout << "- " << c.effect << ": " << c.evidence << "\n";
  std::cout << "\nwhat is left unexplained:\n";
  for (const auto& u : d.unexplained) std::cout << "- " << u << "\n";
}

void run(DiagnosisCliOptions& o, const std::string& force_model) {
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  if (!force_model.empty()) {
    require_extension("--write-force-model", force_model, {".toml"});
    if (block_track_ids(o.data).size() < 2) no_histories(o.data);  // before the diagnosis
  }
  o.values.dt_s = o.model.dt_s;
  diagnosis::DiagnoseOptions opt = diagnose_options(o.values);
  const Model model = o.model.build_model();  // loads plugins first: they become candidates
  const auto in = diagnosis::load_inputs(o.data, o.shape_given ? o.model.shape : "", o.where);
  diagnosis::borrow_floor(opt, o.values, in);
  // Only the weight needs the histories before the diagnosis (force_law_of reads them after it):
  // a set with tracks is not read twice, nor its floor computed, for nothing.
  if (o.history_weight > 0) (void)weigh_histories(opt, o, in);
  opt.progress = !o.output.json;
  const diagnosis::Diagnosis d = diagnosis::diagnose(model, in.shape, in.set, opt);
  nlohmann::json doc = diagnosis::to_json(d);
  if (o.history_weight > 0) doc["history_weight"] = o.history_weight;
  // A set with contact histories: the force the model leaves along each release's own path
  // (issue 33).
  const auto force_law =
      diagnosis::force_law_of(d, o.data, in.set, in.shape, model, o.model.engine_options());
  if (force_law) doc["force_law"] = diagnosis::to_json(*force_law);
  std::vector<std::string> force_model_warnings;
  if (!force_model.empty()) {
    if (!force_law) no_histories(o.data);  // --where left fewer than two
    write_text_file(force_model,
                    diagnosis::with_force_law(model, d.baseline.base.population.params, *force_law,
                                              &force_model_warnings)
                        .to_toml(),
                    "--write-force-model");
    doc["force_model_file"] = force_model;
    doc["force_model_warnings"] = force_model_warnings;
  }
  doc["data"] = o.data;
  doc["shape"] = in.shape.name;
  doc["releases"] = in.set.size();
  std::vector<std::string> figures;
  if (!o.figures.empty()) {
    figures = diagnosis::render_all(diagnosis::diagnose_figures(d, in.shape.name), o.figures);
    doc["figures"] = figures;
  }
  if (!o.output.out.empty()) diagnosis::write_file(o.output.out, d, doc);
  if (!o.write_model.empty()) {
    require_extension("--write-model", o.write_model, {".toml"});
    write_text_file(o.write_model, diagnosis::best_model(model, d).to_toml(), "--write-model");
    doc["model_file"] = o.write_model;
  }
  if (o.output.json) {
    print_json(doc);
    return;
  }
  print_diagnosis(d, o.data, in);
  if (force_law) std::cout << "\n" << diagnosis::format_text(*force_law);
  if (!force_model.empty()) {
    std::cout << "force-law model (the base model at its fit plus the discovered terms): "
              << force_model << "\n";
    for (const auto& w : force_model_warnings) std::cout << "  warning: " << w << "\n";
  }
  std::cout << fmt::format("\n({:.1f} s, {:.2f} million collisions)\n", d.seconds,
                           static_cast<double>(d.collisions) * 1e-6);
  print_written(figures, o.output.out);
}

}  // namespace

void add_diagnose_command(CLI::App& app) {
  auto force_model = std::make_shared<std::string>();
  add_diagnosis_command(
      app, "diagnose",
      "Rank the catalog's effects (and plugins) missing from the model by the held-out error "
      "after adding each one and recalibrating; evidence in words",
      {.alpha = kDiagnosisAlphaHelp,
       .candidates = true,
       .release_fits = true,
       .intervals = true,
       .features = true,
       .write_model = true,
       .history_weight = true},
      [force_model](CLI::App* sub) {
        sub->add_option("--write-force-model", *force_model,
                        "Write the base model at its fit plus the discovered force law's terms "
                        "(term_<name> effects at their coefficients) to FILE (.toml); needs "
                        "contact histories");
      },
      [force_model](DiagnosisCliOptions& o) { run(o, *force_model); });
}

}  // namespace ricochet::cli
