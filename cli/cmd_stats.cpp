// `ricochet stats DATA [--where EXPR] [--json] [--out FILE]`: descriptive statistics of the six
// velocities of an impact set, laid out as paper Table 2. See docs/commands/stats.md.
#include <iostream>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "impact/impact_set.hpp"
#include "shared_options.hpp"
#include "stats/table2.hpp"

namespace ricochet::cli {
namespace {

struct StatsOptions {
  std::string data;
  std::string where;
  OutputOptions output;
};

void run(const StatsOptions& o) {
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  const ImpactSet all = read_impact_set(o.data);
  const ImpactSet set = filter_nonempty(all, o.where, o.data);
  if (set.empty()) throw InputError(o.data, 0, "id", "the impact set has no release");

  const stats::Table2 table = stats::table2(set, o.data, o.where);
  if (!o.output.out.empty()) {
    if (o.output.out.ends_with(".csv"))
      stats::write_csv(o.output.out, table);
    else
      stats::write_h5(o.output.out, table);
  }
  if (o.output.json) {
    print_json(stats::to_json(table));
    return;
  }
  std::cout << stats::format_text(table);
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
