// A campaign design: the impacts to run, read from TOML (docs/commands/dem.md, "Design file").
// Explicit [[impact]] tables, a product design ([design] incident states x angles x seeds x
// [design.vary]) and a space-filling sample over grain-scale parameters ([design.sample]). The
// incident states may come from a plan of throws ([design] plan = "plan.csv", `ricochet design`).
#pragma once

#include <string>
#include <vector>

#include "impact_spec.hpp"
#include "params.hpp"

namespace ricochet::dem {

/// A campaign design (TOML). See docs/commands/dem.md for the keys.
struct CampaignDesign {
  std::string source;  ///< the TOML file
  std::string name;
  int ranks_per_impact = 1;
  std::string cache_dir = "dem-cache";  ///< bed cache (relative paths: to the working directory)
  std::string work_dir = "dem-work";    ///< per-impact folders (log, screen, track)
  /// [campaign] end_wall_rerun_Lx_m [m]: an impact that ends at an end wall (status end_wall) on
  /// a shorter bed is run once more on a bed this long, landing at the same distance from the
  /// back wall (campaign.hpp, end_wall_reruns). 0: no rerun.
  double end_wall_rerun_Lx_m = 0;
  ExtractOptions extract;
  std::vector<ImpactSpec> impacts;  ///< explicit [[impact]] entries, then the [design] product
};

/// Reads and checks a design. Throws InputError(file, line, key) on any bad entry: unknown key or
/// parameter, wrong type, vin not three numbers, duplicate id, empty design.
CampaignDesign read_campaign_design(const std::string& path, const Decks& decks);
/// Same from TOML text; `path` names the file in errors and anchors a relative incident_from.
CampaignDesign parse_campaign_design(const std::string& text, const std::string& path,
                                     const Decks& decks);
/// The design restricted to the impacts whose ids are in `ids`, in the design's order (`dem
/// campaign --only`: a few impacts of a generated design run first, e.g. a paired check's base
/// arm, with the specs the whole design gives them). Throws InputError("<command line>", 0,
/// "--only") naming an id the design does not have, with the design's ids.
CampaignDesign select_impacts(CampaignDesign design, const std::vector<std::string>& ids);

}  // namespace ricochet::dem
