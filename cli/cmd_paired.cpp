// `ricochet paired DATA --base PREFIX --against PREFIX [--lab LAB]... [--margin M] [--level L]
// [--where EXPR] [--json] [--out FILE]`: the paired comparison of two conditions of the same
// impacts (stats/paired.hpp), e.g. the stiffness plateau of docs/resolved-model.md. See
// docs/commands/paired.md.
#include <fmt/format.h>

#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "common/paths.hpp"
#include "impact/impact_set.hpp"
#include "shared_options.hpp"
#include "stats/paired.hpp"

namespace ricochet::cli {
namespace {

struct PairedCliOptions {
  std::vector<std::string> data;  ///< one file, or several whose releases are pooled
  std::string base, against, where;
  std::vector<std::string> lab;  ///< empty: the shipped lab cylinders and triangles
  stats::PairedOptions paired;
  OutputOptions output;
};

// Each shape's scale: the V_out standard deviations of its releases in the lab sets.
std::map<std::string, std::array<double, 3>> lab_scales(const std::vector<std::string>& files) {
  std::map<std::string, std::array<double, 3>> out;
  for (const std::string& f : files) {
    const ImpactSet lab = read_impact_set(f);
    std::map<std::string, ImpactSet> by_shape;
    for (const Impact& im : lab.impacts) {
      ImpactSet& s = by_shape[im.shape];
      s.source = f;
      s.impacts.push_back(im);
    }
    for (const auto& [shape, s] : by_shape) {
      if (out.count(shape))
        throw InputError(
            f, 0, "shape",
            fmt::format("a second lab set for shape '{}' (one --lab per shape)", shape));
      out[shape] = stats::vout_std(s);
    }
  }
  return out;
}

void run(const PairedCliOptions& o) {
  refuse_problems(o.paired.problems(), {{"level", "--level"}, {"margin", "--margin"}});
  require_out_extension(o.output, {".csv"});
  if (o.base == o.against)
    throw InputError("<command line>", 0, "--against", "the same prefix as --base");
  // Several files are pooled (a side study beside its campaign: the floor check's stiff-wall
  // impacts against the plateau campaign's): an id in two of them would pair ambiguously.
  ImpactSet set;
  std::map<std::string, std::string> file_of;
  std::string names;
  for (const std::string& f : o.data) {
    const ImpactSet one = filter_nonempty(read_impact_set(f), o.where, f);
    for (const Impact& im : one.impacts) {
      if (!file_of.emplace(im.id, f).second)
        throw InputError(f, 0, "id",
                         fmt::format("release '{}' is also in {}: pooled files need distinct ids",
                                     im.id, file_of[im.id]));
      set.impacts.push_back(im);
    }
    if (set.source.empty()) set.source = one.source;
    names += (names.empty() ? "" : " + ") + f;
  }
  std::vector<std::string> labs = o.lab;
  if (labs.empty())
    labs = {(data_dir() / "lab" / "cylinders.csv").string(),
            (data_dir() / "lab" / "triangles.csv").string()};
  const stats::PairedComparison c =
      stats::paired_comparison(set, o.base, o.against, lab_scales(labs), o.paired);
  if (!o.output.out.empty()) stats::write_csv(o.output.out, c, names);
  if (o.output.json) {
    print_json(stats::to_json(c));
    return;
  }
  std::cout << stats::format_text(c, names);
  if (!o.output.out.empty()) std::cout << "wrote " << o.output.out << "\n";
}

}  // namespace

void add_paired_command(CLI::App& app) {
  auto options = std::make_shared<PairedCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "paired",
      "Paired comparison of two conditions of the same impacts (ids PREFIX + KEY), e.g. a grain "
      "stiffness or convergence study: mean difference per V_out component in lab standard "
      "deviations, its t interval, and whether it holds");
  sub->add_option("DATA", options->data,
                  "Impact set (.csv, .h5 or .hdf5); several are pooled (their ids must differ)")
      ->required();
  sub->add_option("--base", options->base, "Id prefix of the reference condition, e.g. E1.5e8-")
      ->required();
  sub->add_option("--against", options->against,
                  "Id prefix of the condition compared with it, e.g. E1.5e9- (differences are "
                  "this minus the base)")
      ->required();
  sub->add_option("--lab", options->lab,
                  "Lab set whose V_out standard deviations scale the differences of its shape(s) "
                  "(repeatable; default: data/lab/cylinders.csv and data/lab/triangles.csv)")
      ->check(CLI::ExistingFile);
  sub->add_option("--margin", options->paired.margin,
                  "A component also holds when |mean difference| is below this, in lab sd")
      ->capture_default_str();
  show_range(sub, "--margin", stats::PairedOptions::kMargin);
  sub->add_option("--level", options->paired.level, "Confidence level of the t interval")
      ->capture_default_str();
  show_range(sub, "--level", stats::PairedOptions::kLevel);
  add_where_option(sub, options->where, "the releases of DATA");
  add_output_options(sub, options->output);
  sub->callback([options] { run(*options); });
}

}  // namespace ricochet::cli
