#include "diagnosis_options.hpp"

#include <cmath>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "common/error.hpp"
#include "diagnosis/history_objective.hpp"
#include "shared_options.hpp"

namespace ricochet::cli {

using diagnosis::AssessOptions;
using diagnosis::DiagnoseOptions;

void add_diagnosis_options(CLI::App* sub, diagnosis::OptionValues& v,
                           const DiagnosisOptionSet& set) {
  sub->add_option("--folds", v.folds,
                  "k of the k-fold held-out error, at least 2 (at most the number of releases: "
                  "more are clamped to it), or loro (leave one release out)")
      ->capture_default_str();
  add_seed_option(sub, v.seed,
                  "every random draw: the calibrations' start designs, the cross-validation's "
                  "partitions into folds and the score test's multiplier bootstrap");
  sub->add_option("--repeats", v.repeats,
                  "Partitions of the repeated k-fold held-out error (each a different random "
                  "split into folds)")
      ->capture_default_str();
  show_range(sub, "--repeats", AssessOptions::kRepeats);
  if (set.alpha) {
    sub->add_option("--alpha", v.alpha, set.alpha)->capture_default_str();
    sub->add_option("--screen", v.screen,
                    "At most this many candidates are calibrated (held-out error) after the score "
                    "test: those it supports, at least the best")
        ->capture_default_str();
    sub->add_option("--adequate-z", v.adequate_z,
                    "The verdict is adequate only if every family's weakest detectable law "
                    "(80 % power) changes the predictions by at most this noncentrality z; "
                    "otherwise inconclusive (docs/diagnosis.md, Verdict)")
        ->capture_default_str();
    sub->add_flag("--no-pairs", v.no_pairs,
                  "Do not try pairs of candidates when no single one is enough");
  }
  if (set.candidates)
    sub->add_option("--candidate", v.candidates,
                    "Only try these effects (repeatable); default: every registered effect not "
                    "in the model");
  if (set.release_fits)
    sub->add_flag("--no-release-fits", v.no_release_fits,
                  "Skip the per-release calibration (no parameter-drift evidence; faster)");
  if (set.intervals)
    sub->add_flag("--no-intervals", v.no_intervals,
                  "Per-release fits without identifiability intervals (faster)");
  if (set.features) {
    sub->add_flag("--no-features", v.no_features,
                  "Ignore penetration and contact duration even when the data have them");
    sub->add_option("--floor-replicates", v.floor_replicates,
                    "Impact set with replicate releases on the same ground (e.g. a campaign's "
                    "bed-position pairs): its pooled scatter is the noise floor of DATA when DATA "
                    "has no replicates of its own");
    sub->add_option("--floor-where", v.floor_where,
                    "Keep only the --floor-replicates releases matching EXPR (the --where syntax, "
                    "e.g. \"id^=E1.5e9-\": one level of a campaign)")
        ->needs("--floor-replicates");
  }
  sub->add_option("--error", v.error,
                  "Error denominators: set-mean (Eq. 7 floored at the set's mean magnitude) or "
                  "eq7 (the paper's)")
      ->capture_default_str();
  add_orientation_options(sub, v.orientations, v.polish_orientations);
  sub->add_option("--orientation-starts", v.orientation_starts,
                  "At least this many BOBYQA runs in every cold fit (full set and folds) of a "
                  "set with releases of unknown orientation, in " +
                      fit::FitOptions::kStarts.text())
      ->capture_default_str();
  sub->add_option("--search-xtol", v.search_xtol,
                  "BOBYQA step tolerance of the orientation search's runs, whose best ends are "
                  "polished on the refined rule (units of the bound range), in " +
                      fit::FitOptions::kUnitFraction.text())
      ->capture_default_str();
  sub->add_option("--orientation-search", v.orientation_search,
                  "Global search of cold fits on sets of unknown orientation: multistart "
                  "(BOBYQA runs on the search rule, the best ends polished) or surface (a "
                  "response surface over collisions on the refined rule, docs/diagnosis.md)")
      ->capture_default_str();
  add_threads_option(sub, v.threads);
  if (set.alpha) {
    show_range(sub, "--alpha", DiagnoseOptions::kAlpha);
    show_range(sub, "--screen", DiagnoseOptions::kScreen);
    show_range(sub, "--adequate-z", DiagnoseOptions::kAdequateZ);
  }
}

const OptionNames& diagnosis_option_names() {
  static const OptionNames names = {{"alpha", "--alpha"},
                                    {"screen", "--screen"},
                                    {"adequate_z", "--adequate-z"},
                                    {"assess.folds", "--folds"},
                                    {"assess.repeats", "--repeats"},
                                    {"assess.fit.alpha.marginal_points", "--orientations"},
                                    {"assess.fit.alpha.polish_points", "--polish-orientations"},
                                    {"assess.marginal_starts", "--orientation-starts"},
                                    {"assess.fit.alpha.search_xtol", "--search-xtol"},
                                    {"assess.fit.engine.dt_s", "--dt"}};
  return names;
}

diagnosis::DiagnoseOptions diagnose_options(const diagnosis::OptionValues& values) {
  diagnosis::DiagnoseOptions o = diagnosis::make_options(values);
  refuse_problems(o.problems(), diagnosis_option_names());
  return o;
}

CLI::App* add_diagnosis_command(CLI::App& app, const std::string& name,
                                const std::string& description, const DiagnosisOptionSet& set,
                                const std::function<void(CLI::App*)>& extra,
                                const std::function<void(DiagnosisCliOptions&)>& run) {
  auto o = std::make_shared<DiagnosisCliOptions>();
  CLI::App* sub = app.add_subcommand(name, description);
  sub->add_option("DATA", o->data, "Impact set (.csv, .h5)")->required();
  add_where_option(sub, o->where, "the releases of DATA");
  add_model_options(sub, o->model);
  if (extra) extra(sub);
  add_diagnosis_options(sub, o->values, set);
  if (set.history_weight) {
    sub->add_option("--history-weight", o->history_weight,
                    "Calibrate on the contact histories too: every population fit minimises Eq. "
                    "7 plus W x (each history's RMS error / its replicate floor)^2 per release "
                    "(W = the V_out floor weighs a force floor as a rebound floor; "
                    "docs/diagnosis.md, \"Calibrated on the histories too\")");
    check_range(sub, "--history-weight", 1e-12, 1e6);
  }
  add_figures_option(sub, o->figures);
  if (set.write_model)
    sub->add_option("--write-model", o->write_model,
                    "Write the best model found (with its calibrated values) as a model file "
                    "(.toml) that calibrate, ladder, montecarlo and sobol read");
  add_output_options(sub, o->output);
  sub->callback([o, sub, run] {
    o->shape_given = sub->get_option("--shape")->count() > 0;
    run(*o);
  });
  return sub;
}

SetHistories weigh_histories(diagnosis::DiagnoseOptions& opt, const DiagnosisCliOptions& o,
                             const diagnosis::Inputs& in) {
  SetHistories h;
  h.histories = diagnosis::measured_histories(o.data, in.set, in.shape);
  if (diagnosis::history_count(h.histories) > 0)
    h.floor =
        diagnosis::force_history_floor(in.set, in.shape, h.histories, opt.assess.borrowed_floor);
  if (!(o.history_weight > 0)) return h;
  if (diagnosis::history_count(h.histories) < 2)
    throw InputError("<command line>", 0, "--history-weight",
                     o.data + " keeps no contact histories of two releases or more");
  const auto objective = diagnosis::history_objective(
      in.set, h.histories,
      h.floor ? h.floor->rms : std::array<double, diagnosis::kForceComponents>{NAN, NAN, NAN},
      o.history_weight, in.shape, o.model.engine_options(), "--history-weight");
  opt.assess.fit.extra_objective = [objective](const Model& m, std::span<const double> p,
                                               const ImpactSet& s) {
    return (*objective)(m, p, s);
  };
  return h;
}

void print_force_history(const std::vector<std::string>& rungs,
                         const std::vector<diagnosis::ForceHistoryError>& errors,
                         const std::optional<diagnosis::ForceHistoryScatter>& floor) {
  if (errors.empty()) return;
  std::cout << fmt::format(
      "\nforce histories ({} releases, {} contact samples; RMS of measured minus model, "
      "in-sample / held-out +- its standard error over releases):\n{:<5}{:<22}{:>30}{:>30}{:>30}\n",
      errors.front().releases, errors.front().samples, "rung", "added", "normal [N]",
      "tangential [N]", "moment [N m]");
  for (std::size_t r = 0; r < errors.size(); ++r) {
    std::string line = fmt::format("{:<5}{:<22}", r, rungs[r]);
    for (std::size_t c = 0; c < diagnosis::kForceComponents; ++c)
      line += std::isfinite(errors[r].insample_rms[c])
                  ? fmt::format("{:>12.4g} /{:>8.4g} +-{:<6.3g}", errors[r].insample_rms[c],
                                errors[r].heldout_rms[c], errors[r].heldout_se[c])
                  : fmt::format("{:>30}", "-");
    if (floor) {
      line += "   x floor";
      for (std::size_t c = 0; c < diagnosis::kForceComponents; ++c)
        line += std::isfinite(errors[r].heldout_rms[c] / floor->rms[c])
                    ? fmt::format(" {:.2f}", errors[r].heldout_rms[c] / floor->rms[c])
                    : std::string(" -");  // a component not measured (no torque tracked)
    }
    std::cout << line << "\n";
  }
  if (!floor) return;
  std::string line = fmt::format("{:<5}{:<22}", "", "replicate floor");
  for (std::size_t c = 0; c < diagnosis::kForceComponents; ++c)
    line += std::isfinite(floor->rms[c])
                ? fmt::format("{:>12} /{:>8.4g}{:8}", "", floor->rms[c], "")
                : fmt::format("{:>30}", "-");
  std::cout << line << "\n"
            << fmt::format(
                   "     (one history's RMS distance from its replicates' mean history, {} groups "
                   "of {} histories{}{}; moment about the lowest point)\n",
                   floor->groups, floor->histories,
                   floor->source.empty() ? "" : ", borrowed from " + floor->source,
                   floor->where.empty() ? "" : " (" + floor->where + ")");
}

void print_written(const std::vector<std::string>& figures, const std::string& out) {
  for (const auto& f : figures) std::cout << "wrote " << f << "\n";
  if (!out.empty()) std::cout << "wrote " << out << "\n";
}

}  // namespace ricochet::cli
