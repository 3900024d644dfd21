// A campaign of resolved impacts: a design (campaign_design.hpp) distributed over MPI ranks (one
// LIGGGHTS instance per group of ranks, MPI_Comm_split), written impact by impact to the campaign
// file (campaign_store.hpp) so that a killed campaign resumes where it stopped.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "campaign_design.hpp"
#include "campaign_store.hpp"

namespace ricochet::dem {

struct CampaignOptions {
  std::string out;             ///< results (.h5); resumed when it exists
  bool retry_crashed = false;  ///< rerun impacts that were running when a previous run died
  bool progress = true;        ///< progress bar on a terminal (world rank 0)
  /// ParaView output of every impact run by this call (docs/paraview.md): VTK frames every
  /// vtk_every steps (0 = none) in vtk_dir/<impact id>/.
  std::string vtk_dir;
  long vtk_every = 0;
  /// Store the picture of the design's first impact (/dem/snapshot, impact/impact_snapshot.hpp):
  /// VTK frames every kDefaultVtkEvery steps during that impact (about 20 s on the default bed),
  /// removed once cut, unless vtk_every asked for them.
  bool picture = true;
};

struct CampaignSummary {
  std::vector<CampaignEntry> entries;  ///< in the file's order (world rank 0 only)
  std::size_t ran = 0;                 ///< impacts run by this call (all ranks)
  std::size_t skipped = 0;             ///< already in the file (resumed)
  std::size_t reruns = 0;              ///< end-wall reruns in the design now (end_wall_reruns)
  int groups = 0;                      ///< LIGGGHTS instances run in parallel
  double wall_s = 0;
};

/// One impact of a design as a dry run sees it (plan_campaign).
struct PlannedImpact {
  std::string id;
  std::string bed_key;        ///< its bed's cache key (bed.hpp)
  bool bed_cached = false;    ///< the design's cache_dir holds that bed
  bool bed_building = false;  ///< not cached, and a process is building it now (bed_building)
  std::string status;         ///< its status in the campaign file; empty: still to run
  std::string spec;           ///< the impact as the campaign file records it (spec_json)
  /// Why the driver would refuse it before LIGGGHTS (status `invalid`, validate_setup: e.g. a
  /// run-up that starts behind the back wall's margin), checked on its bed when that bed is
  /// cached; empty when it passes or its bed is not built yet.
  std::string invalid;
};

/// The reruns that `design.end_wall_rerun_Lx_m` (L) asks for, given the campaign file's `index`:
/// for every impact of the design recorded there as `end_wall` on a bed shorter than L, the same
/// impact on a bed L long (bed.Lx_m = L: the same grains, pouring and replica seed, so a new bed
/// poured from the same seeds in a longer box) landing at the same distance from the back wall
/// (run.x_impact_frac times the old length over L), id `ID-LxL` (e.g. `sandv00-p09-x0.26-Lx1.5`),
/// in design order. The rest of the spec is kept: a sampled design's rerun has its design point's
/// grain parameters, so that calibrate-grains counts it among that point's replicas. The
/// original stays in the file as end_wall. Empty when L is 0. Why: a block that rides the bed long
/// reaches the wall ahead before it leaves, so a fixed bed length censors one side of the response
/// (docs/resolved-model.md, "Recalibration with what sand has").
std::vector<ImpactSpec> end_wall_reruns(const CampaignDesign& design, const Decks& decks,
                                        const std::vector<CampaignEntry>& index);

/// What run_campaign would do with `design` and the campaign file `out` (which need not exist),
/// without running anything: every impact in design order with its bed, whether the cache holds
/// the bed, and whether the file already has the impact (read under the file's shared lock, so a
/// running campaign's file can be planned against), then the end-wall reruns of the impacts the
/// file records at an end wall so far (a rerun of an impact not run yet cannot be known). `ricochet
/// dem campaign --dry-run`.
std::vector<PlannedImpact> plan_campaign(const CampaignDesign& design, const Decks& decks,
                                         const std::string& out);

/// Records in the campaign file `out` (record_bed_packing) the packing of every bed on which the
/// file has an impact of `design` (its end-wall reruns included) and which it does not record
/// yet: measured on the cached bed, or on the bed built again from the same seeds when the cache
/// lacks it (a new machine: about half an hour a bed at 1.5e9 Pa), the cached ones first.
/// Collective on `world`, the beds dealt over the groups; returns the keys of the beds it recorded.
/// run_campaign records each bed itself after its first impact; this is for files written before it
/// did, or whose beds were measured nowhere. `ricochet dem campaign --record-beds`.
std::vector<std::string> record_beds(const CampaignDesign& design, const Decks& decks,
                                     const std::string& out, MPI_Comm world);

/// Runs the pending impacts of `design` on `world` (collective), then their end-wall reruns
/// (end_wall_reruns, with no picture), and returns the summary.
CampaignSummary run_campaign(const CampaignDesign& design, const Decks& decks,
                             const CampaignOptions& options, MPI_Comm world);

}  // namespace ricochet::dem
