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
  std::string data, base, against, where;
  std::vector<std::string> lab;  ///< empty: the shipped lab cylinders and triangles
  stats::PairedOptions paired;
  OutputOptions output;
};

constexpr std::array<const char*, 3> kComponents = {"V_out^x", "V_out^y", "omega_out"};
constexpr std::array<const char*, 3> kKeys = {"vout_x", "vout_y", "wout"};

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

nlohmann::json to_json(const stats::PairedComparison& c,
                       const std::map<std::string, std::array<double, 3>>& scales) {
  nlohmann::json comps = nlohmann::json::object();
  for (std::size_t k = 0; k < 3; ++k) {
    const stats::PairedComponent& x = c.components[k];
    const auto num = [](double v) {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
    };
    comps[kKeys[k]] = {{"n", x.n},
                       {"mean", num(x.mean)},
                       {"sd", num(x.sd)},
                       {"interval", {num(x.lo), num(x.hi)}},
                       {"interval_holds_zero", x.interval_holds_zero},
                       {"within_margin", x.within_margin},
                       {"holds", x.holds}};
  }
  nlohmann::json pairs = nlohmann::json::array();
  for (std::size_t i = 0; i < c.keys.size(); ++i)
    pairs.push_back(
        {{"key", c.keys[i]},
         {"shape", c.shapes[i]},
         {"difference", {c.differences[i][0], c.differences[i][1], c.differences[i][2]}}});
  nlohmann::json sc = nlohmann::json::object();
  for (const auto& [shape, s] : scales) sc[shape] = {s[0], s[1], s[2]};
  return {{"base", c.base},
          {"against", c.other},
          {"level", c.options.level},
          {"margin", c.options.margin},
          {"scales", sc},
          {"pairs", pairs},
          {"unpaired", c.unpaired},
          {"components", comps},
          {"all_hold", c.all_hold}};
}

void run(const PairedCliOptions& o) {
  require_out_extension(o.output, {".csv"});
  const ImpactSet set = filter_nonempty(read_impact_set(o.data), o.where, o.data);
  std::vector<std::string> labs = o.lab;
  if (labs.empty())
    labs = {(data_dir() / "lab" / "cylinders.csv").string(),
            (data_dir() / "lab" / "triangles.csv").string()};
  const auto scales = lab_scales(labs);
  if (o.base == o.against)
    throw InputError("<command line>", 0, "--against", "the same prefix as --base");
  const stats::PairedComparison c =
      stats::paired_comparison(set, o.base, o.against, scales, o.paired);

  if (!o.output.out.empty()) {
    CsvTable t;
    t.comment(
        fmt::format("ricochet paired {}: {} minus {}, in lab standard deviations of each "
                    "shape's V_out",
                    o.data, o.against, o.base));
    t.row({"key", "shape", "d_vout_x[sd]", "d_vout_y[sd]", "d_wout[sd]"});
    for (std::size_t i = 0; i < c.keys.size(); ++i)
      t.row({c.keys[i], c.shapes[i], CsvTable::num(c.differences[i][0]),
             CsvTable::num(c.differences[i][1]), CsvTable::num(c.differences[i][2])});
    t.write(o.output.out);
  }
  if (o.output.json) {
    print_json(to_json(c, scales));
    return;
  }
  std::cout << fmt::format(
      "{}: {} minus {}, {} pair{}; differences in lab standard deviations of each shape's "
      "V_out\n",
      o.data, o.against, o.base, c.keys.size(), c.keys.size() == 1 ? "" : "s");
  std::cout << fmt::format("{:<10} {:>3} {:>8} {:>7}   {:<22} {}\n", "component", "n", "mean", "sd",
                           fmt::format("{:.0f} % interval", 100 * o.paired.level), "holds");
  for (std::size_t k = 0; k < 3; ++k) {
    const stats::PairedComponent& x = c.components[k];
    const std::string why = x.n < 2 ? "fewer than 2 pairs: no interval"
                            : x.interval_holds_zero && x.within_margin
                                ? "interval holds 0, |mean| < margin"
                            : x.interval_holds_zero ? "interval holds 0"
                            : x.within_margin       ? "|mean| < margin"
                                                    : "moves";
    std::cout << fmt::format("{:<10} {:>3} {:>+8.3f} {:>7.3f}   [{:+.3f}, {:+.3f}]{:>5} {} ({})\n",
                             kComponents[k], x.n, x.mean, x.sd, x.lo, x.hi, "",
                             x.holds ? "yes" : "no", why);
  }
  std::cout << fmt::format("all components hold (margin {} sd): {}\n", o.paired.margin,
                           c.all_hold ? "yes" : "no");
  if (!c.unpaired.empty()) {
    std::string ids;
    for (const auto& id : c.unpaired) ids += (ids.empty() ? "" : ", ") + id;
    std::cout << "unpaired: " << ids << "\n";
  }
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
  sub->add_option("DATA", options->data, "Impact set (.csv, .h5 or .hdf5)")->required();
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
  check_range(sub, "--margin", 0, 100);
  sub->add_option("--level", options->paired.level, "Confidence level of the t interval")
      ->capture_default_str();
  check_range(sub, "--level", 0.5, 0.999);
  add_where_option(sub, options->where, "the releases of DATA");
  add_output_options(sub, options->output);
  sub->callback([options] { run(*options); });
}

}  // namespace ricochet::cli
