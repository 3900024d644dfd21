// `ricochet stats DATA [--where EXPR] [--json] [--out FILE]`: descriptive statistics of the six
// velocities of an impact set, laid out as paper Table 2, and of its impacts' tracks when the
// file keeps them (a resolved campaign's /dem/tracks). A plan of throws (incident states only) is
// summarised too, without V_out. See docs/commands/stats.md.
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "impact/impact_set.hpp"
#include "shared_options.hpp"
#include "stats/campaign_outcomes.hpp"
#include "stats/table2.hpp"
#include "stats/track_summary.hpp"

namespace ricochet::cli {
namespace {

struct StatsOptions {
  std::string data;
  std::string where;
  OutputOptions output;
};

void run(const StatsOptions& o) {
  require_out_extension(o.output, {".csv", ".h5", ".hdf5"});
  // The incident-state reader is the impact-set reader that also takes a plan of throws (CSV
  // without the three reflected columns, docs/impact-sets.md "Incident states").
  const ImpactSet all = read_incident_states(o.data);
  const ImpactSet set = filter_nonempty(all, o.where, o.data);
  if (set.empty()) throw InputError(o.data, 0, "id", "the impact set has no release");
  bool plan = true;
  for (const auto& im : set.impacts) plan = plan && std::isnan(im.vout[kVy]);

  const stats::Table2 table = stats::table2(set, o.data, o.where);
  const stats::TrackTable tracks = stats::track_table(o.data, set);
  const bool has_tracks = !tracks.impacts.empty() || tracks.other_tracks > 0;
  const stats::CampaignOutcomes outcomes = stats::campaign_outcomes(o.data, all, o.where);
  if (!o.output.out.empty()) {
    if (o.output.out.ends_with(".csv"))
      stats::write_csv(o.output.out, table);
    else
      stats::write_h5(o.output.out, table);
  }
  if (o.output.json) {
    nlohmann::json doc = stats::to_json(table);
    doc["incident_only"] = plan;
    doc["tracks"] = has_tracks ? stats::to_json(tracks) : nlohmann::json(nullptr);
    doc["outcomes"] = outcomes.impacts > 0 ? stats::to_json(outcomes) : nlohmann::json(nullptr);
    print_json(doc);
    return;
  }
  std::cout << stats::format_text(table);
  if (plan) std::cout << "Incident states only (a plan of throws): no reflected velocities.\n";
  if (has_tracks) std::cout << "\n" << stats::format_text(tracks);
  if (outcomes.impacts > 0) std::cout << "\n" << stats::format_text(outcomes);
  if (!o.output.out.empty()) std::cout << "wrote " << o.output.out << "\n";
}

}  // namespace

void add_stats_command(CLI::App& app) {
  auto options = std::make_shared<StatsOptions>();
  CLI::App* sub = app.add_subcommand(
      "stats",
      "Mean, sample standard deviation, coefficient of variation, min and max of the six "
      "velocities of an impact set (paper Table 2), and the contacts of its tracks when the file "
      "keeps them (/dem/tracks)");
  sub->add_option("DATA", options->data,
                  "Impact set or plan of throws (.csv, .h5 or .hdf5); a campaign file's tracks too")
      ->required();
  add_where_option(sub, options->where, "the releases of DATA");
  add_output_options(sub, options->output);
  sub->callback([options] { run(*options); });
}

}  // namespace ricochet::cli
