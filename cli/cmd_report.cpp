// `ricochet report DATA [DATA ...] --out report.html`: the self-contained HTML validation report
// (data, comparison, diagnosis, model ladder, conclusions) for every shape of every impact set
// given (docs/commands/report.md).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <list>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "diagnosis/inputs.hpp"
#include "diagnosis/validation_report.hpp"
#include "diagnosis_options.hpp"
#include "fit/fit.hpp"
#include "impact/release_index.hpp"
#include "model_options.hpp"
#include "shared_options.hpp"

namespace ricochet::cli {
namespace {

struct ReportCliOptions {
  std::vector<std::string> data;
  std::vector<std::string> labels;
  std::vector<std::string> against;
  std::string where;
  std::vector<std::string> data_where;   ///< one filter per DATA file ("" = none), after --where
  std::vector<std::string> data_floors;  ///< a borrowed floor's file per DATA file ("" = none)
  std::vector<std::string> data_floor_where;  ///< its filter per DATA file ("" = all)
  ModelOptions model;
  diagnosis::OptionValues values;
  OutputOptions output;
  diagnosis::ReportOptions report;  ///< --rounds, --title: their defaults are the library's
  bool shape_given = false;
};

// A set run at the lab's releases (every impact's id names one: a verification campaign, a half
// of it under --data-where) is compared with those releases only, like with like; `lab` is cut to
// them and true returned. Otherwise (a design of its own, synthetic data) `lab` stays whole.
bool keep_matched_releases(ImpactSet& lab, const ImpactSet& set) {
  if (set.empty()) return false;
  const ReleaseIndex index(lab);
  std::vector<char> used(lab.size(), 0);
  for (const Impact& im : set.impacts) {
    const auto r = index.find(im.id);
    if (!r) return false;
    used[*r] = 1;
  }
  std::vector<Impact> kept;
  for (std::size_t i = 0; i < lab.size(); ++i)
    if (used[i]) kept.push_back(lab.impacts[i]);
  lab.impacts = std::move(kept);
  return true;
}

// An option given once per DATA file, in order, or not at all: any other count is refused,
// naming the option (`what`: one of its values; `none`: how a file without one is written).
void require_one_per_data(std::size_t given, std::size_t data, const char* option, const char* what,
                          const char* none) {
  if (given != 0 && given != data)
    throw InputError("<command line>", 0, option,
                     fmt::format("give one {} per DATA file ({}{})", what, data, none));
}

void run(ReportCliOptions& o) {
  require_extension("--out", o.output.out, {".html", ".htm"});
  o.values.dt_s = o.model.dt_s;
  diagnosis::ReportOptions ro = o.report;
  ro.diagnose = diagnosis::make_options(o.values);
  ro.diagnose.progress = !o.output.json;
  OptionNames names = {{"rounds", "--rounds"}};
  for (const auto& [field, name] : diagnosis_option_names())
    names.emplace_back("diagnose." + field, name);
  refuse_problems(ro.problems(), names);
  require_one_per_data(o.labels.size(), o.data.size(), "--label", "label", "");
  require_one_per_data(o.data_where.size(), o.data.size(), "--data-where", "filter",
                       "; \"\" for none");
  require_one_per_data(o.data_floors.size(), o.data.size(), "--data-floor-replicates", "file",
                       "; \"\" for none");
  require_one_per_data(o.data_floor_where.size(), o.data.size(), "--data-floor-where", "filter",
                       "; \"\" for none");
  for (std::size_t f = 0; f < o.data_floor_where.size(); ++f)
    if (!o.data_floor_where[f].empty() && o.data_floors[f].empty())
      throw InputError("<command line>", 0, "--data-floor-where",
                       fmt::format("'{}' filters DATA file {} ({})'s borrowed floor, but its "
                                   "--data-floor-replicates is \"\"",
                                   o.data_floor_where[f], f + 1, o.data[f]));
  const Model model = o.model.build_model();

  // --against: the measured sets each input of the same shape is compared with.
  std::vector<std::pair<std::string, ImpactSet>> labs;
  for (const auto& path : o.against) labs.emplace_back(path, read_impact_set(path));
  std::list<ImpactSet> lab_subsets;  // one per (lab, shape) used: stable addresses for inputs
  std::vector<diagnosis::ReportInput> inputs;
  for (std::size_t f = 0; f < o.data.size(); ++f) {
    const ImpactSet all =
        filter_nonempty(filter_nonempty(read_impact_set(o.data[f]), o.where, o.data[f]),
                        o.data_where.empty() ? "" : o.data_where[f], o.data[f], "--data-where");
    const std::vector<std::string> shapes =
        diagnosis::shapes_to_analyse(all, o.shape_given ? o.model.shape : "");
    for (const auto& sh : shapes) {
      diagnosis::Inputs selected = diagnosis::select_inputs(all, sh, o.data[f]);
      diagnosis::ReportInput in;
      in.data = o.data[f];
      in.shape = std::move(selected.shape);
      in.set = std::move(selected.set);
      if (!o.data_floors.empty() && !o.data_floors[f].empty())
        in.borrowed_floor = diagnosis::borrowed_scatter(
            o.data_floors[f], in.shape.name, "--data-floor-replicates",
            o.data_floor_where.empty() ? "" : o.data_floor_where[f], "--data-floor-where");
      const std::string stem = std::filesystem::path(o.data[f]).stem().string();
      in.label = (o.labels.empty() ? stem : o.labels[f]) +
                 (shapes.size() > 1 || o.labels.empty() ? " (" + in.shape.name + ")" : "");
      for (const auto& [path, lab] : labs) {
        if (std::filesystem::equivalent(path, o.data[f])) continue;  // the lab itself
        ImpactSet same = lab.with_shape(in.shape.name);
        if (same.empty()) continue;
        in.lab_matched = keep_matched_releases(same, in.set);
        in.lab = &lab_subsets.emplace_back(std::move(same));
        in.lab_data = path;
        break;
      }
      inputs.push_back(std::move(in));
    }
  }
  const auto sections = diagnosis::analyse(inputs, model, ro);
  const std::size_t figures = diagnosis::write_report(sections, model, ro, o.output.out);
  if (o.output.json) {
    print_json(
        {{"out", o.output.out}, {"figures", figures}, {"sets", diagnosis::to_json(sections)}});
    return;
  }
  for (const auto& s : sections) std::cout << "- " << s.conclusion << "\n";
  std::cout << fmt::format("wrote {} ({} figures embedded)\n", o.output.out, figures);
}

}  // namespace

void add_report_command(CLI::App& app) {
  auto o = std::make_shared<ReportCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "report",
      "Self-contained HTML validation report (data, comparison, diagnosis, model ladder, "
      "conclusions) for every shape of every impact set given");
  sub->add_option("DATA", o->data, "Impact sets (.csv, .h5): lab data, LIGGGHTS campaigns, ...")
      ->required();
  sub->add_option("--label", o->labels, "A label per DATA file, in order (repeatable)");
  sub->add_option("--against", o->against,
                  "Measured set (e.g. data/lab/cylinders.csv) each DATA set of its shape is "
                  "compared with: means, KS, robust, without the lab's gross errors (repeatable)")
      ->check(CLI::ExistingFile);
  add_where_option(sub, o->where, "the releases of each DATA");
  sub->add_option("--data-where", o->data_where,
                  "A filter per DATA file, in order (\"\" for none), after --where: e.g. the same "
                  "campaign twice, its held-out and its calibration half (repeatable)");
  sub->add_option("--data-floor-replicates", o->data_floors,
                  "A file per DATA file, in order (\"\" for none): an impact set with replicate "
                  "releases on the same ground whose pooled scatter is that DATA's noise floor "
                  "when it has no replicates of its own (compare's --floor-replicates; "
                  "repeatable)");
  sub->add_option("--data-floor-where", o->data_floor_where,
                  "A filter per DATA file, in order (\"\" for all): the releases of its "
                  "--data-floor-replicates file that lend their scatter (compare's --floor-where; "
                  "repeatable)")
      ->needs("--data-floor-replicates");
  add_model_options(sub, o->model);
  sub->add_option("--rounds", o->report.rounds,
                  "Effects the automatic ladder may add (rounds of diagnosis after the first)")
      ->capture_default_str();
  show_range(sub, "--rounds", diagnosis::ReportOptions::kRounds);
  sub->add_option("--title", o->report.title, "Title of the page")->capture_default_str();
  add_diagnosis_options(sub, o->values, {.alpha = kDiagnosisAlphaHelp, .intervals = true});
  add_output_options(sub, o->output, JsonOut::kRefused);
  sub->get_option("--out")->required()->description("The HTML file to write");
  sub->callback([o, sub] {
    o->shape_given = sub->get_option("--shape")->count() > 0;
    run(*o);
  });
}

}  // namespace ricochet::cli
