// `ricochet dem drop`: spheres dropped vertically into a resolved bed from several heights, the
// bed's angle of repose, and the checks against Uehara et al. 2003 (PRL 90, 194301) and
// Katsuragi & Durian 2007 (Nature Physics 3, 420); and `ricochet dem repose`, the angle of
// repose alone (the same repose run, in the column geometry asked for). See docs/commands/dem.md
// ("dem drop", "dem repose") and docs/granular-impact-checks.md. The study and its analysis are
// src-ext's (drop_study.hpp, drop_analysis.hpp): this file binds the options and prints.
#include <mpi.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "drop_analysis.hpp"
#include "drop_store.hpp"
#include "drop_study.hpp"
#include "mpi_session.hpp"

namespace ricochet::cli {
namespace {

using nlohmann::json;

struct DropOptions {
  dem::DropStudyOptions study;
  std::vector<std::string> sets;
  std::string decks;
  OutputOptions output;
};

// The run's provenance around the analysis: output file, ranks, decks, bed, what was asked.
json run_json(const DropOptions& o, const dem::Decks& decks, const dem::DropStudySets& sets,
              const dem::DropStudyRun& run, int ranks) {
  const dem::BedFiles& bed = run.bed;
  return {{"out", o.output.out},
          {"ranks", ranks},
          {"decks_digest", dem::drop_decks_digest(decks)},
          {"bed_decks_digest", decks.bed_decks_digest()},
          {"bed",
           {{"key", bed.key},
            {"mode", bed.mode},
            {"grains", bed.grains},
            {"Lx_m", bed.Lx_m},
            {"Ly_m", bed.Ly_m},
            {"H_m", bed.H_m},
            {"z_surface_m", bed.z_surface_m},
            {"dt_s", bed.dt_s},
            {"r_max_m", bed.r_max_m},
            {"values", bed.values}}},
          {"drop_overrides", sets.base.drop},
          {"block_overrides", sets.base.block},
          {"seeds", o.study.seeds},
          {"heights_m", o.study.heights_m},
          {"ran_now", run.fresh.size()}};
}

void run_drop_command_on_rank(const DropOptions& o, const MpiSession& mpi) {
  const auto decks = dem::Decks::locate(o.decks);
  const dem::DropStudySets sets = dem::parse_drop_sets(decks, o.sets);
  const std::string& out = o.output.out;
  if (!out.empty()) require_extension("--out", out, {".csv"});
  for (double h : o.study.heights_m)
    if (!(h > 0)) throw InputError("<command line>", 0, "--heights", "heights must be > 0");
  // Drops already in the file are skipped (resume), and its repose run is read back.
  const std::optional<dem::DropStore> store =
      out.empty() ? std::nullopt : std::optional<dem::DropStore>(dem::DropStore(out));
  const std::set<std::string> done = store ? store->done_ids() : std::set<std::string>{};
  const dem::StudyFriction friction =
      dem::study_friction(decks, sets, o.study, store ? store->repose_path() : "", MPI_COMM_WORLD);
  const dem::DropStudyRun run =
      dem::run_drop_study(decks, sets, o.study, done, store ? &*store : nullptr, MPI_COMM_WORLD,
                          [](const dem::DropResult& r) {
                            std::cerr << fmt::format("[dem drop] {}: {} ({}) in {:.0f} s\n", r.id,
                                                     r.status, r.message, r.wall_s);
                          });
  if (mpi.rank() != 0) return;

  const dem::DropStudyAnalysis analysis = dem::analyse_drop_study(
      dem::study_drops(store ? &*store : nullptr, run), friction.mu, run.bed, o.study.analysis);
  if (o.output.json) {
    json j = dem::to_json(analysis);
    j.update(dem::to_json(friction));
    j.update(run_json(o, decks, sets, run, mpi.size()));
    print_json(j);
    return;
  }
  std::cout << fmt::format("dem drop: {} drops ({} at rest, {} run now), mu = {:.3f} ({})\n",
                           analysis.drops.size(), analysis.n_at_rest, run.fresh.size(), friction.mu,
                           friction.imposed ? "imposed" : "repose run");
  std::cout << dem::to_text(analysis);
}

void run_drop_command(const DropOptions& o) {
  MpiSession mpi;
  mpi.run([&] { run_drop_command_on_rank(o, mpi); });
}

struct ReposeOptions {
  std::vector<std::string> sets;
  std::optional<long> seed;
  std::string decks;
  std::string work_dir = "dem-work";
  OutputOptions output;
};

void run_repose_command_on_rank(const ReposeOptions& o, const MpiSession& mpi) {
  const auto decks = dem::Decks::locate(o.decks);
  dem::DropStudySets sets = dem::parse_drop_sets(decks, o.sets);
  // The repose deck has neither the sphere nor the block: their settings would be ignored.
  if (!sets.base.drop.empty() || !sets.base.block.empty())
    throw InputError("<command line>", 0, "--set",
                     "the repose deck reads only bed.* (the grains) and repose.* (the column): "
                     "drop.* and block.* belong to `dem drop` and `dem impact`");
  require_out_extension(o.output, {});
  if (o.seed) sets.base.seed = *o.seed;
  const dem::ReposeResult r =
      dem::run_repose(decks, dem::drop_bed_overrides(sets.base), sets.repose,
                      (std::filesystem::path(o.work_dir) / "repose").string(), MPI_COMM_WORLD);
  if (mpi.rank() != 0) return;
  json j = dem::repose_to_json(r);
  j["ranks"] = mpi.size();
  j["decks_digest"] = dem::drop_decks_digest(decks);
  j["bed_overrides"] = sets.base.bed;
  j["repose_overrides"] = sets.repose;
  if (o.seed) j["seed"] = *o.seed;
  if (o.output.json) {
    print_json(j);
  } else {
    std::cout << fmt::format("dem repose: {} ({} grains, {:.0f} s)\n", r.message, r.grains,
                             r.wall_s);
  }
  // A heap without a flank to fit is a failed measurement, not a result (exit 1; the JSON above
  // says why).
  if (r.status == "failed") throw std::runtime_error("dem repose: " + r.message);
}

}  // namespace

void add_dem_repose_command(CLI::App& dem) {
  auto o = std::make_shared<ReposeOptions>();
  auto* s = dem.add_subcommand(
      "repose",
      "Angle of repose of a bed's grains: a column collapsed into a heap, its flank fitted");
  s->add_option("--set", o->sets,
                "SECTION.NAME=VALUE, SECTION bed (the grains, as for every dem command) or repose "
                "(repose/in.repose: L_col_m, H_col_m, L_floor_m, W_m, t_collapse_max_s); "
                "repeatable");
  s->add_option("--seed", o->seed, "Replica seed of the column's grains (default: the decks' own)");
  s->add_option("--decks", o->decks, "liggghts-inputs folder");
  s->add_option("--work", o->work_dir, "Work folder (the run's log and final grains in repose/)");
  add_output_options(s, o->output);
  s->get_option("--out")->description(
      "Write the --json document (with the heap's surface profile) to FILE.json");
  check_range(s, "--seed", 0, 1e6);
  s->callback([o] {
    MpiSession mpi;
    mpi.run([&] { run_repose_command_on_rank(*o, mpi); });
  });
}

void add_dem_drop_command(CLI::App& dem) {
  auto o = std::make_shared<DropOptions>();
  dem::DropStudyOptions& study = o->study;
  auto* s = dem.add_subcommand(
      "drop", "Drop a sphere into a bed from several heights; Uehara and Katsuragi-Durian checks");
  s->add_option("--heights", study.heights_m, "Drop heights [m] (sphere bottom above the surface)")
      ->delimiter(',');
  s->add_option("--seeds", study.seeds,
                "Replica seeds (a bed per seed; default: the decks' own seeds, one bed)")
      ->delimiter(',');
  s->add_option("--set", o->sets,
                "SECTION.NAME=VALUE, SECTION bed, block, drop (drop/setup.in) or repose "
                "(repose/in.repose); repeatable");
  s->add_option("--decks", o->decks, "liggghts-inputs folder");
  s->add_option("--cache", study.cache_dir, "Bed cache folder");
  s->add_option("--work", study.work_dir, "Work folder (per-drop logs and tracks)");
  s->add_option("--mu", study.mu,
                "Impose mu = tan(repose angle) instead of running the repose deck");
  s->add_option("--half-window", study.analysis.analysis.half_window,
                "Derivative half-window [records]");
  s->add_option("--stop-fraction", study.analysis.analysis.stop_fraction,
                "End of the fitted penetration phase: speed below this x impact speed");
  s->add_option("--tolerance", study.analysis.tolerance, "Largest |exponent - 1/3| that passes");
  add_output_options(s, o->output, JsonOut::kRefused);
  check_range(s, "--heights", 1e-4, 10);
  check_range(s, "--seeds", 0, 1e6);
  check_range(s, "--mu", 0, 10);
  check_range(s, "--half-window", 1, 1000);
  check_range(s, "--stop-fraction", 0, 1);
  check_range(s, "--tolerance", 0, 1);
  s->callback([o] { run_drop_command(*o); });
}

}  // namespace ricochet::cli
