// A campaign of resolved impacts: a design read from TOML, distributed over MPI ranks (one
// LIGGGHTS instance per group of ranks, MPI_Comm_split), written impact by impact to HDF5 so that
// a killed campaign resumes where it stopped. File format: docs/commands/dem.md.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "impact_run.hpp"
#include "params.hpp"

namespace ricochet::dem {

/// A campaign design (TOML). See docs/commands/dem.md for the keys.
struct CampaignDesign {
  std::string source;  ///< the TOML file
  std::string name;
  int ranks_per_impact = 1;
  std::string cache_dir = "dem-cache";  ///< bed cache (relative paths: to the working directory)
  std::string work_dir = "dem-work";    ///< per-impact folders (log, screen, track)
  ExtractOptions extract;
  std::vector<ImpactSpec> impacts;  ///< explicit [[impact]] entries, then the [design] product
};

/// Reads and checks a design. Throws InputError(file, line, key) on any bad entry: unknown key or
/// parameter, wrong type, vin not three numbers, duplicate id, empty design.
CampaignDesign read_campaign_design(const std::string& path, const Decks& decks);

struct CampaignOptions {
  std::string out;             ///< results (.h5); resumed when it exists
  bool retry_crashed = false;  ///< rerun impacts that were running when a previous run died
  bool progress = true;        ///< progress bar on a terminal (world rank 0)
};

/// One row of the campaign index (every impact that ended, whatever its status).
struct CampaignEntry {
  std::string id, status, message, shape, bed_key, work_dir;
  std::string params;  ///< JSON: the spec (spec_json) plus "effective" bed and block parameters
  std::vector<double> values;  ///< aligned with campaign_value_names()
};
/// Numeric columns of /dem/index/values.
const std::vector<std::string>& campaign_value_names();

struct CampaignSummary {
  std::vector<CampaignEntry> entries;  ///< in the file's order (world rank 0 only)
  std::size_t ran = 0;                 ///< impacts run by this call (all ranks)
  std::size_t skipped = 0;             ///< already in the file (resumed)
  int groups = 0;                      ///< LIGGGHTS instances run in parallel
  double wall_s = 0;
};

/// Runs the pending impacts of `design` on `world` (collective) and returns the summary.
CampaignSummary run_campaign(const CampaignDesign& design, const Decks& decks,
                             const CampaignOptions& options, MPI_Comm world);

/// Appends one finished impact to the campaign file `path` (under an flock on PATH.lock): its
/// track, its index row, then rewrites /impacts (the impact-set schema) from the index.
/// `params_json` records the spec. Used by run_campaign and by `ricochet dem impact --out`.
void append_result(const std::string& path, const ImpactResult& result, const ImpactSpec& spec,
                   const std::string& design_name);

/// Reads the index of a campaign file (empty when the file or the index does not exist).
std::vector<CampaignEntry> read_campaign_index(const std::string& path);

/// JSON record of a spec (shape, vin, alpha, seed, overrides).
std::string spec_json(const ImpactSpec& spec);
/// spec_json plus the impact's effective grain-scale parameters ("effective": {"bed", "block"}).
std::string params_json(const ImpactSpec& spec, const ImpactResult& result);

}  // namespace ricochet::dem
