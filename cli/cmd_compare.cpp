// `ricochet compare DATA --model FILE [--shape S]`: where does the model fail? Calibrates the
// model (population and per release, through the fit module), then reports errors per
// observable, per release and per regime, residual and parameter trends against impact
// features, measured-vs-predicted KS tests, the noise floor and whether the model is adequate
// (docs/commands/compare.md).
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "diagnosis/figures.hpp"
#include "diagnosis/force_history.hpp"
#include "diagnosis/inputs.hpp"
#include "diagnosis_options.hpp"
#include "model_options.hpp"

namespace ricochet::cli {
namespace {

void run(DiagnosisCliOptions& o) {
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  o.values.dt_s = o.model.dt_s;
  diagnosis::DiagnoseOptions opt = diagnose_options(o.values);
  const Model model = o.model.build_model();
  const auto in = diagnosis::load_inputs(o.data, o.shape_given ? o.model.shape : "", o.where);
  diagnosis::borrow_floor(opt, o.values, in);
  const auto [histories, force_floor] = weigh_histories(opt, o, in);
  const diagnosis::Baseline b = diagnosis::compare(model, in.shape, in.set, opt);
  nlohmann::json doc = diagnosis::to_json(b, in.set);
  // A set with contact histories: the calibrated model's force along each release's own path,
  // in-sample and at its splits' fits (issue 33), whether or not the fits weighed them.
  std::vector<diagnosis::ForceHistoryError> force_errors;
  if (diagnosis::history_count(histories) >= 2) {
    force_errors.push_back(diagnosis::force_history_error(model, in.shape, b.base, histories,
                                                          o.model.engine_options()));
    doc["force_history"] = diagnosis::to_json(force_errors.front());
    if (force_floor) doc["force_history_floor"] = diagnosis::to_json(*force_floor);
  }
  if (o.history_weight > 0) doc["history_weight"] = o.history_weight;
  doc["data"] = o.data;
  doc["shape"] = in.shape.name;
  doc["verdict"] = b.adequacy.adequate ? "adequate" : "not adequate";
  std::vector<std::string> figures;
  if (!o.figures.empty()) {
    figures =
        diagnosis::render_all(diagnosis::compare_figures(b, in.set, in.shape.name), o.figures);
    doc["figures"] = figures;
  }
  if (!o.output.out.empty()) diagnosis::write_file(o.output.out, b, in.set, doc);
  if (o.output.json) {
    print_json(doc);
    return;
  }
  const auto& a = b.base;
  std::cout << fmt::format("{} ({} releases of shape {}), model:", o.data, in.set.size(),
                           in.shape.name);
  for (const auto& e : a.effects) std::cout << " " << e;
  std::cout << "\npopulation fit:";
  for (std::size_t i : a.population.calibrated)
    std::cout << fmt::format(" {} = {:.4g}", a.population.names[i], a.population.params[i]);
  std::cout << fmt::format("\nnoise floor {:.4g} ({}: {}); nearest-neighbour check {:.4g}\n",
                           b.floor.value.mean, b.floor.source, b.floor.description,
                           b.floor.nearest_neighbour);
  std::cout << fmt::format(
      "error (Eq. 7{}): in-sample {:.4g}, held-out {:.4g} +- {:.2g} ({}-fold) = {:.2f} x floor: "
      "{}\n\n",
      a.use[diagnosis::kObsPenetration] || a.use[diagnosis::kObsDuration] ? " + contact terms" : "",
      a.insample.error.mean, a.heldout.error.mean, a.heldout.error.se, a.folds, b.adequacy.ratio,
      b.adequacy.adequate ? "ADEQUATE (within the noise floor)" : "NOT adequate");
  std::cout << fmt::format("{:<18}{:>12}{:>12}{:>12}{:>14}{:>10}\n", "observable", "in-sample",
                           "held-out", "floor", "held-out RMSE", "KS p");
  for (int k = 0; k < diagnosis::kObservables; ++k)
    if (a.use[k])
      std::cout << fmt::format("{:<18}{:>12.4g}{:>12.4g}{:>12.4g}{:>10.3g} {:<3}{:>10.2g}\n",
                               diagnosis::kObservableLabels[k], a.insample.term_mean[k],
                               a.heldout.term_mean[k], b.floor.term_mean[k], a.heldout.rmse[k],
                               diagnosis::kObservableUnits[k], b.ks[k].p_value);
  std::cout << "\nper regime (held-out error vs floor):\n";
  for (const auto& r : b.regimes)
    std::cout << fmt::format("  {:<40} n = {:>3}  {:.4g} +- {:.2g}  (floor {:.4g})\n", r.name,
                             r.releases.size(), r.heldout.mean, r.heldout.se, r.floor.mean);
  std::cout << "\nper release (held-out error, worst first):\n";
  std::vector<std::size_t> order(in.set.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return a.heldout.per_release[x] > a.heldout.per_release[y];
  });
  for (std::size_t r = 0; r < std::min<std::size_t>(order.size(), 8); ++r) {
    const std::size_t i = order[r];
    std::cout << fmt::format("  {:<8} {:.4g}  (floor {:.3g})\n", in.set.impacts[i].id,
                             a.heldout.per_release[i], b.floor.per_release[i]);
  }
  std::cout << "\nsignificant trends (p < " << opt.trends.alpha << "):\n";
  int shown = 0;
  for (const auto* trends : {&b.residual_trends, &b.parameter_trends})
    for (const auto& t : *trends)
      if (t.significant) std::cout << "  " << diagnosis::describe(t) << "\n", ++shown;
  if (shown == 0) std::cout << "  none\n";
  print_force_history({"(model)"}, force_errors, force_floor);
  print_written(figures, o.output.out);
}

}  // namespace

void add_compare_command(CLI::App& app) {
  add_diagnosis_command(
      app, "compare",
      "Calibrate a model on an impact set and show where it fails: errors per observable, "
      "release and regime, residual and parameter trends, CDFs, noise floor",
      {.release_fits = true, .intervals = true, .features = true, .history_weight = true}, {}, run);
}

}  // namespace ricochet::cli
