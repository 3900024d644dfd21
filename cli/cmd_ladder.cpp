// `ricochet ladder DATA --shape S --model FILE --add NAME [--add NAME ...] --json`: recalibrate
// each rung (base, + first effect, + second effect, ...) and show the error falling towards the
// noise floor, in-sample and held-out, per observable (docs/commands/ladder.md). With --auto N
// the rungs are chosen by rounds of `ricochet diagnose`.
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "diagnosis/figures.hpp"
#include "diagnosis/force_history.hpp"
#include "diagnosis/inputs.hpp"
#include "diagnosis_options.hpp"
#include "impact/block_track.hpp"
#include "model_options.hpp"

namespace ricochet::cli {
namespace {

// Refuses a ladder without rungs, an unknown --add and --force-law on a file without histories,
// before any work.
void check_rungs(const std::vector<std::string>& adds, int auto_rounds, bool force_law,
                 const std::string& data) {
  const auto& registry = EffectRegistry::global();
  for (const auto& a : adds) {
    try {
      (void)registry.get(a);  // its error lists the known effects
    } catch (const std::exception& e) {
      throw InputError("<command line>", 0, "--add", e.what());
    }
  }
  if (adds.empty() && auto_rounds < 0 && !force_law)
    throw InputError("<command line>", 0, "--add",
                     "give the effects of the ladder (--add NAME, repeatable), --auto N or "
                     "--force-law");
  if (force_law && block_track_ids(data).size() < 2)
    throw InputError("<command line>", 0, "--force-law",
                     data +
                         " keeps no contact histories of two releases or more (a campaign "
                         "file's /dem/tracks): there is no force law to discover");
}

void print_rungs(const diagnosis::Ladder& l) {
  const auto& use = l.rungs.front().assessment.use;
  std::string head = fmt::format("{:<5}{:<22}{:>11}{:>11}{:>9}{:>10}", "rung", "added", "in-sample",
                                 "held-out", "+-SE", "x floor");
  for (int k = 0; k < diagnosis::kObservables; ++k)
    if (use[k]) head += fmt::format("{:>13}", diagnosis::kObservableNames[k]);
  std::cout << head << "\n";
  for (std::size_t r = 0; r < l.rungs.size(); ++r) {
    const auto& rung = l.rungs[r];
    const auto& a = rung.assessment;
    std::string line =
        fmt::format("{:<5}{:<22}{:>11.4g}{:>11.4g}{:>9.2g}{:>10.2f}", r,
                    rung.added.empty() ? "(base)" : "+" + rung.added, a.insample.error.mean,
                    a.heldout.error.mean, a.heldout.error.se, rung.adequacy.ratio);
    for (int k = 0; k < diagnosis::kObservables; ++k)
      if (use[k]) line += fmt::format("{:>13.4g}", a.heldout.term_mean[k]);
    std::cout << line << (rung.adequacy.adequate ? "  adequate" : "") << "\n";
    if (!rung.law.empty()) std::cout << "     law: " << rung.law << "\n";
  }
  std::string floor_line = fmt::format("{:<5}{:<22}{:>11}{:>11.4g}{:>9}{:>10}", "", "noise floor",
                                       "", l.floor.value.mean, "", "");
  for (int k = 0; k < diagnosis::kObservables; ++k)
    if (use[k]) floor_line += fmt::format("{:>13.4g}", l.floor.term_mean[k]);
  std::cout << floor_line << "\n";
}

void run(DiagnosisCliOptions& o, int auto_rounds, bool force_law,
         const std::vector<std::string>& force_terms) {
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  o.values.dt_s = o.model.dt_s;
  diagnosis::DiagnoseOptions opt = diagnose_options(o.values);
  const std::vector<std::string> adds = o.model.add;
  ModelOptions base_options = o.model;
  base_options.add.clear();
  const Model model = base_options.build_model();  // loads plugins, reads --model, applies --set
  check_rungs(adds, auto_rounds, force_law, o.data);
  const auto named = diagnosis::named_force_terms(force_terms, "<command line>", "--force-terms");
  const auto in = diagnosis::load_inputs(o.data, o.shape_given ? o.model.shape : "", o.where);
  diagnosis::borrow_floor(opt, o.values, in);
  const auto [histories, force_floor] = weigh_histories(opt, o, in);
  opt.assess.release_fits = opt.assess.release_fits && auto_rounds >= 0;
  opt.progress = !o.output.json;
  diagnosis::Ladder l = auto_rounds >= 0
                            ? diagnosis::auto_ladder(model, in.shape, in.set, auto_rounds, opt)
                            : diagnosis::ladder(model, in.shape, in.set, adds, opt);
  std::optional<diagnosis::ForceLawReport> discovered;
  if (force_law)
    discovered = diagnosis::add_force_law_rung(l, model, in.shape, in.set, o.data, opt, named);
  const auto force_errors =
      diagnosis::ladder_force_history(model, l, in.shape, histories, o.model.engine_options());
  nlohmann::json doc = diagnosis::to_json(l);
  if (discovered) doc["force_law"] = diagnosis::to_json(*discovered);
  if (!force_errors.empty()) {
    doc["force_history"] = nlohmann::json::array();
    for (const auto& e : force_errors) doc["force_history"].push_back(diagnosis::to_json(e));
  }
  if (force_floor && !force_errors.empty())
    doc["force_history_floor"] = diagnosis::to_json(*force_floor);
  if (o.history_weight > 0) doc["history_weight"] = o.history_weight;
  doc["data"] = o.data;
  doc["shape"] = in.shape.name;
  std::vector<std::string> figures;
  if (!o.figures.empty()) {
    figures = diagnosis::render_all(diagnosis::ladder_figures(l, in.shape.name), o.figures);
    doc["figures"] = figures;
  }
  if (!o.output.out.empty()) diagnosis::write_file(o.output.out, l, doc);
  if (!o.write_model.empty()) {
    require_extension("--write-model", o.write_model, {".toml"});
    write_text_file(o.write_model, diagnosis::ladder_model(model, l).to_toml(), "--write-model");
    doc["model_file"] = o.write_model;
  }
  if (o.output.json) {
    print_json(doc);
    return;
  }
  std::cout << fmt::format("{} ({} releases of shape {}); noise floor {:.4g} ({})\n\n", o.data,
                           in.set.size(), in.shape.name, l.floor.value.mean, l.floor.source);
  print_rungs(l);
  std::vector<std::string> rungs;
  for (const auto& r : l.rungs) rungs.push_back(r.added.empty() ? "(base)" : "+" + r.added);
  print_force_history(rungs, force_errors, force_floor);
  if (discovered) std::cout << "\n" << diagnosis::format_text(*discovered);
  if (!l.stop_reason.empty()) std::cout << "\nstopped: " << l.stop_reason << "\n";
  print_written(figures, o.output.out);
}

}  // namespace

void add_ladder_command(CLI::App& app) {
  auto auto_rounds = std::make_shared<int>(-1);
  auto force_law = std::make_shared<bool>(false);
  auto force_terms = std::make_shared<std::vector<std::string>>();
  add_diagnosis_command(
      app, "ladder",
      "Recalibrate a ladder of models (base, + effect, + another, ...) and show the in-sample "
      "and held-out error falling towards the noise floor",
      {.alpha = "--auto: the family-wise error rate of each round's candidate tests (as "
                "diagnose --alpha)",
       .features = true,
       .write_model = true,
       .history_weight = true},
      [auto_rounds, force_law, force_terms](CLI::App* sub) {
        auto* law = sub->add_flag("--force-law", *force_law,
                                  "Last rung: the force law discovered on the file's contact "
                                  "histories, its terms held at their discovered coefficients "
                                  "(needs /dem/tracks)");
        sub->add_option("--force-terms", *force_terms,
                        "--force-law: fit these library terms (e.g. ploughing viscous; "
                        "docs/effects/force_term.md) on the histories instead of selecting "
                        "terms: a named law, its coefficients from the histories of each "
                        "split's training releases")
            ->needs(law);
        sub->get_option("--add")->description(
            "Effect added by the next rung (repeatable, in order; plugin effects too)");
        sub->add_option("--auto", *auto_rounds,
                        "Choose the rungs by rounds of diagnose, at most N effects (instead of "
                        "--add)");
        check_range(sub, "--auto", 1, 20);
      },
      [auto_rounds, force_law, force_terms](DiagnosisCliOptions& o) {
        run(o, *auto_rounds, *force_law, *force_terms);
      });
}

}  // namespace ricochet::cli
