// `ricochet calibrate-grains CAMPAIGN.h5 --lab LAB.csv`: the resolved bed's grain parameters
// calibrated against measured rebounds through a kriging surrogate of a sampled campaign
// ([design.sample]), with its leave-one-out validation and Sobol indices. See
// docs/commands/calibrate-grains.md and docs/resolved-model.md ("Calibration of the grains").
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "engine/shape.hpp"
#include "fit/fit.hpp"
#include "grain_calibration.hpp"
#include "impact/impact_set.hpp"
#include "mpi_session.hpp"
#include "params.hpp"
#include "shared_options.hpp"
#include "stats/lab_gap.hpp"

namespace ricochet::cli {
namespace {

struct Options {
  std::string campaign, lab, lab_where, shape = "cylinder", figures, decks;
  bool without_gross_errors = false;
  /// --where, --parameters and --seed write into the library's options (and show its defaults).
  dem::GrainCalibrationOptions calibration;
  OutputOptions output;
};

void run(const Options& o) {
  if (!o.output.out.empty()) require_extension("--out", o.output.out, {".json"});
  const auto decks = dem::Decks::locate(o.decks);
  const Shape shape = Shape::resolve(o.shape);
  std::vector<std::string> dropped;
  ImpactSet lab = fit::select_shape(
      filter_nonempty(read_impact_set(o.lab), o.lab_where, o.lab, "--lab-where"), shape);
  const std::size_t n_matching = lab.size();
  if (o.without_gross_errors) lab = stats::without_gross_errors(lab, &dropped);
  // Measuring the beds' packing runs LIGGGHTS, which needs MPI.
  std::optional<MpiSession> mpi;
  if (!o.calibration.bed_cache.empty()) mpi.emplace();
  const auto r = dem::calibrate_grains(o.campaign, decks, lab, o.calibration);
  std::vector<std::string> figures;
  if (!o.figures.empty()) figures = dem::write_grain_calibration_figures(r, o.figures);
  nlohmann::json j = nlohmann::json::parse(dem::grain_calibration_json(r));
  j["target"] = o.lab;
  j["target_where"] = o.lab_where;
  j["target_without"] = dropped;
  j["figures"] = figures;
  if (!o.output.out.empty()) write_text_file(o.output.out, stamp_json(j).dump(1), "--out");
  if (o.output.json) {
    print_json(j);
    return;
  }
  std::cout << fmt::format(
      "calibrate-grains {}: {} design points ({} impacts did not rebound), {} parameters, {:.1f} "
      "s\n",
      r.source, r.points.size(), r.failed, r.parameters.size(), r.seconds);
  if (!o.lab_where.empty())
    std::cout << fmt::format("  target: the {} releases of {} that match --lab-where\n", n_matching,
                             o.lab);
  if (o.without_gross_errors) {
    std::string ids;
    for (const auto& id : dropped) ids += (ids.empty() ? "" : ", ") + id;
    std::cout << fmt::format("  target: {} without its gross errors ({})\n", o.lab,
                             ids.empty() ? "none" : ids);
  }
  const char* names[3] = {"V_out^x", "V_out^y", "omega_out"};
  for (int c = 0; c < 3; ++c) {
    std::cout << fmt::format(
        "  {:9}: LOO Q2 = {:.2f} (RMSE {:.3g}), replicate sd {:.3g}; target {:.3f} +- {:.3f}, "
        "calibrated {:.3f} +- {:.3f} ({:+.2f} target sd)\n",
        names[c], r.q2[c], r.rmse_loo[c], r.replicate_sd[c], r.target_mean[c], r.target_sd[c],
        r.best_mean[c], r.best_sd[c], (r.best_mean[c] - r.target_mean[c]) / r.target_sd[c]);
    std::string s;
    for (std::size_t k = 0; k < r.parameters.size(); ++k)
      s += fmt::format(" {} {:.2f}/{:.2f}", r.parameters[k], r.first[c][k], r.total[c][k]);
    std::cout << "    Sobol first/total:" << s << "\n";
  }
  std::cout << "  calibrated grain parameters (decks' default in brackets):\n";
  for (std::size_t k = 0; k < r.parameters.size(); ++k)
    std::cout << fmt::format("    {} = {:.4g}  [{:.4g}]  (sampled {:.4g} .. {:.4g})\n",
                             r.parameters[k], r.best[k], r.deck_default[k], r.lower[k], r.upper[k]);
  std::cout << fmt::format(
      "  expected misfit J = {:.2f}; {:.1f} % of the sampled box is within 0.5 target sd on every "
      "component\n",
      r.best_misfit, 100 * r.acceptable_fraction);
  if (std::isfinite(r.best_solid_fraction)) {
    const auto [lo, hi] = dem::solid_fraction_range(r);
    std::cout << fmt::format(
        "  packing: the design's beds have solid fractions {:.3f} .. {:.3f} (LOO Q2 {:.2f}); "
        "calibrated point {:.3f} +- {:.3f}",
        lo, hi, r.solid_fraction_q2, r.best_solid_fraction, r.best_solid_fraction_sd);
    if (r.solid_fraction_band.size() == 2)
      std::cout << fmt::format(", searched within [{:.3f}, {:.3f}]", r.solid_fraction_band[0],
                               r.solid_fraction_band[1]);
    std::cout << "\n";
    for (const auto& e : r.grain_count_estimates)
      std::cout << fmt::format(
          "    {} bed(s) from their grain count on {} recorded bed(s) of their geometry "
          "(leave-one-out error at most {:.4f})\n",
          e.beds.size(), e.references, e.loo_max_abs);
  }
  if (!r.rebound_points.empty()) {
    std::size_t rebounds = 0, counted = 0, none = 0;
    for (const auto& t : r.rebound_points) {
      rebounds += t.rebounds;
      counted += t.counted;
      none += t.rebounds == 0;
    }
    std::cout << fmt::format(
        "  rebounds: {} of {} counted impacts; {} of {} design points never rebounded", rebounds,
        counted, none, r.rebound_points.size());
    if (r.rebound_threshold > 0)
      std::cout << fmt::format(
          "; searched where the rebound indicator is >= {} ({:.1f} % of the box, leave-one-out "
          "agreement {:.0f} %), calibrated point {:.2f}",
          r.rebound_threshold, 100 * r.rebound_box_fraction, 100 * r.rebound_loo_agreement,
          r.best_rebound);
    std::cout << "\n";
  }
  if (r.admissible_fraction < 1)
    std::cout << fmt::format("  the search's constraints leave {:.1f} % of the sampled box\n",
                             100 * r.admissible_fraction);
  for (const auto& f : figures) std::cout << "  figure: " << f << "\n";
}

}  // namespace

void add_calibrate_grains_command(CLI::App& app) {
  auto o = std::make_shared<Options>();
  auto* sub = app.add_subcommand(
      "calibrate-grains",
      "Calibrate the resolved bed's grain parameters to measured rebounds (kriging surrogate)");
  sub->add_option("campaign", o->campaign,
                  "Campaign file of `ricochet dem campaign` with a [design.sample] (.h5)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--lab", o->lab, "Target impact set (e.g. data/lab/cylinders.csv)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--lab-where", o->lab_where,
                  "Keep only the --lab releases matching EXPR (the --where grammar, "
                  "docs/impact-sets.md), e.g. a calibration half from scripts/lab-split.py");
  sub->add_option("--shape", o->shape, "Shape of the target's impacts to use (cylinder, triangle)");
  sub->add_flag("--without-gross-errors", o->without_gross_errors,
                "Leave out the --lab releases that the gross-error rule flags (|modified z| > 3.5 "
                "on any velocity; stats/lab_gap.hpp): the target is the rest's mean and sd");
  sub->add_option("--parameters", o->calibration.parameters,
                  "Surrogate inputs, e.g. bed.mu_gg block.mur_gb (default: those that vary)");
  sub->add_option("--bed-cache", o->calibration.bed_cache,
                  "The campaign's bed cache folder: measure each design point's solid fraction "
                  "on its bed (LIGGGHTS reads the restart files)")
      ->check(CLI::ExistingDirectory);
  sub->add_flag(
      "--packing-from-grain-count", o->calibration.packing_from_grain_count,
      "Report the design's packing; a bed neither recorded in the campaign file nor in "
      "--bed-cache: estimate its solid fraction from its grain count and the recorded beds of "
      "its geometry (the estimate's leave-one-out error on them is printed)");
  sub->add_option("--solid-fraction", o->calibration.solid_fraction,
                  "LO,HI: search the calibrated point only where the solid fraction's surrogate "
                  "is within [LO, HI] (a sand-like bed; each bed's packing from the file's "
                  "record, --bed-cache or --packing-from-grain-count)")
      ->delimiter(',')
      ->expected(2);
  sub->add_option("--rebound-threshold", o->calibration.rebound_threshold,
                  "Search the calibrated point only where the indicator kriging of the design's "
                  "rebounds (timeouts, no_rebound and end walls without a longer rerun count as "
                  "none) is at least P (default: the lab's 28 rebounds in 28, lower 95 % "
                  "bound); 0 turns it off")
      ->capture_default_str();
  check_range(sub, "--rebound-threshold", 0, 0.999);
  // Not applied to --lab (as upscale): the filter may name the campaign's own columns.
  add_where_option(sub, o->calibration.where, "the campaign's impacts");
  add_figures_option(sub, o->figures);
  sub->add_option("--decks", o->decks, "liggghts-inputs folder (for the parameters' defaults)");
  add_seed_option(sub, o->calibration.seed, "the Sobol and search samples");
  sub->add_flag("--json", o->output.json, "Print one machine-readable JSON document on stdout");
  sub->add_option("--out", o->output.out, "Write the JSON document to FILE (.json)");
  sub->callback([o] { run(*o); });
}

}  // namespace ricochet::cli
