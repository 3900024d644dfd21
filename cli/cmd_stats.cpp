// `ricochet stats DATA [--where EXPR] [--json] [--out FILE]`: descriptive statistics of the six
// velocities of an impact set, laid out as paper Table 2. See docs/commands/stats.md.
#include <array>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "impact/impact_set.hpp"
#include "shared_options.hpp"
#include "stats/stats.hpp"

namespace ricochet::cli {
namespace {

struct StatsOptions {
  std::string data;
  std::string where;
  OutputOptions output;
};

// The six velocities in the column order of paper Table 2.
struct Column {
  const char* name;
  const char* unit;
  const char* label;
};
constexpr std::array<Column, 6> kColumns = {{
    {"vin_x", "m/s", "V_in^x"},
    {"vout_x", "m/s", "V_out^x"},
    {"vin_y", "m/s", "V_in^y"},
    {"vout_y", "m/s", "V_out^y"},
    {"win", "rad/s", "omega_in"},
    {"wout", "rad/s", "omega_out"},
}};

void write_csv(const std::string& path, const std::string& source, const std::string& where,
               std::size_t n, const std::array<stats::Summary, 6>& s) {
  CsvTable t;
  t.comment(fmt::format("ricochet stats of {} ({} releases)", source, n));
  if (!where.empty()) t.comment("where: " + where);
  t.comment("std: sample standard deviation (n - 1); cv = std / mean (signed)");
  t.row({"column", "unit", "n", "mean", "std", "cv", "min", "max"});
  for (std::size_t k = 0; k < kColumns.size(); ++k)
    t.row({kColumns[k].name, kColumns[k].unit, std::to_string(s[k].n), CsvTable::num(s[k].mean),
           CsvTable::num(s[k].std), CsvTable::num(s[k].cv), CsvTable::num(s[k].min),
           CsvTable::num(s[k].max)});
  t.write(path);
}

void write_h5(const std::string& path, const std::string& source, const std::string& where,
              std::size_t n, const std::array<stats::Summary, 6>& s) {
  h5::File file(path, h5::File::Mode::kTruncate);
  std::vector<std::string> names, units;
  std::vector<double> count, mean, sd, cv, min, max;
  for (std::size_t k = 0; k < kColumns.size(); ++k) {
    names.emplace_back(kColumns[k].name);
    units.emplace_back(kColumns[k].unit);
    count.push_back(static_cast<double>(s[k].n));
    mean.push_back(s[k].mean);
    sd.push_back(s[k].std);
    cv.push_back(s[k].cv);
    min.push_back(s[k].min);
    max.push_back(s[k].max);
  }
  file.write_strings("/stats/column", names);
  file.write_strings("/stats/unit", units);
  file.write("/stats/n", count);
  file.write("/stats/mean", mean);
  file.write("/stats/std", sd);
  file.write("/stats/cv", cv);
  file.write("/stats/min", min);
  file.write("/stats/max", max);
  file.set_attr("/stats", "source", source);
  file.set_attr("/stats", "where", where);
  file.set_attr("/stats", "releases", static_cast<double>(n));
  file.flush();
}

void print_table(const std::string& source, const std::string& where, std::size_t n,
                 const std::array<stats::Summary, 6>& s) {
  std::cout << fmt::format("{} ({} releases{})\n", source, n,
                           where.empty() ? std::string() : ", where " + where);
  std::string head = fmt::format("{:<10}", "");
  std::string units = head;
  for (const auto& c : kColumns) {
    head += fmt::format("{:>11}", c.label);
    units += fmt::format("{:>11}", std::string("[") + c.unit + "]");
  }
  std::cout << head << "\n" << units << "\n";
  auto row = [&](const char* label, auto value, const char* format) {
    std::string line = fmt::format("{:<10}", label);
    for (std::size_t k = 0; k < s.size(); ++k)
      line += fmt::format(fmt::runtime(format), value(s[k]));
    std::cout << line << "\n";
  };
  row(
      "mean", [](const stats::Summary& x) { return x.mean; }, "{:>11.3f}");
  row(
      "std", [](const stats::Summary& x) { return x.std; }, "{:>11.3f}");
  row(
      "cv [%]", [](const stats::Summary& x) { return 100.0 * x.cv; }, "{:>11.1f}");
  row(
      "min", [](const stats::Summary& x) { return x.min; }, "{:>11.2f}");
  row(
      "max", [](const stats::Summary& x) { return x.max; }, "{:>11.2f}");
  std::cout << "std: sample standard deviation (n - 1); cv = std / mean, signed as in paper "
               "Table 2.\n";
}

void run(const StatsOptions& o) {
  if (!o.output.out.empty()) require_extension("--out", o.output.out, {".csv", ".h5", ".hdf5"});
  const ImpactSet all = read_impact_set(o.data);
  const ImpactSet set = filter_nonempty(all, o.where, o.data);
  if (set.empty()) throw InputError(o.data, 0, "id", "the impact set has no release");

  std::array<stats::Summary, 6> summaries;
  for (std::size_t k = 0; k < kColumns.size(); ++k)
    summaries[k] = stats::summarize(set.feature(kColumns[k].name));

  if (!o.output.out.empty()) {
    if (o.output.out.ends_with(".csv"))
      write_csv(o.output.out, o.data, o.where, set.size(), summaries);
    else
      write_h5(o.output.out, o.data, o.where, set.size(), summaries);
  }
  if (o.output.json) {
    nlohmann::json doc;
    doc["source"] = o.data;
    doc["n"] = set.size();
    doc["where"] = o.where.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.where);
    nlohmann::json columns = nlohmann::json::object();
    for (std::size_t k = 0; k < kColumns.size(); ++k) {
      const stats::Summary& s = summaries[k];
      // nlohmann::json writes NaN (e.g. std of a single release) as null.
      columns[kColumns[k].name] = {{"mean", s.mean}, {"std", s.std}, {"cv", s.cv},
                                   {"min", s.min},   {"max", s.max}, {"unit", kColumns[k].unit}};
    }
    doc["columns"] = columns;
    print_json(doc);
    return;
  }
  print_table(o.data, o.where, set.size(), summaries);
  if (!o.output.out.empty()) std::cout << "wrote " << o.output.out << "\n";
}

}  // namespace

void add_stats_command(CLI::App& app) {
  auto options = std::make_shared<StatsOptions>();
  CLI::App* sub = app.add_subcommand(
      "stats",
      "Mean, sample standard deviation, coefficient of variation, min and max of the six "
      "velocities of an impact set (paper Table 2)");
  sub->add_option("DATA", options->data, "Impact set (.csv, .h5 or .hdf5)")->required();
  add_where_option(sub, options->where, "the releases of DATA");
  add_output_options(sub, options->output);
  sub->callback([options] { run(*options); });
}

}  // namespace ricochet::cli
