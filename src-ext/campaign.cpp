#include "campaign.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include "bed.hpp"
#include "campaign_schedule.hpp"
#include "common/clock.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/progress.hpp"
#include "engine/shape.hpp"
#include "impact_run.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

namespace {

// Last line starting with ERROR in a LIGGGHTS screen or log file: LIGGGHTS stopped the process
// (error->all ends it with exit()). Empty when there is none: the run was killed from outside.
std::string last_error(const std::string& dir) {
  std::string found;
  for (const char* f : {"screen.txt", "log.liggghts"}) {
    std::ifstream in(fs::path(dir) / f);
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("ERROR", 0) == 0) found = line;
    if (!found.empty()) return found;
  }
  return "";
}
}  // namespace

std::vector<ImpactSpec> end_wall_reruns(const CampaignDesign& design, const Decks& decks,
                                        const std::vector<CampaignEntry>& index) {
  std::vector<ImpactSpec> reruns;
  const double L = design.end_wall_rerun_Lx_m;
  if (!(L > 0)) return reruns;
  std::set<std::string> at_wall;
  for (const auto& e : index)
    if (e.status == "end_wall") at_wall.insert(e.id);
  for (const ImpactSpec& spec : design.impacts) {
    if (!at_wall.count(spec.id)) continue;
    const double Lx = bed_param(decks, spec.params.bed, "Lx_m");
    if (!(Lx < L)) continue;
    ImpactSpec s = spec;
    s.id = fmt::format("{}-Lx{}", spec.id, shortest_number(L));
    s.params.bed["Lx_m"] = shortest_number(L);
    s.params.run["x_impact_frac"] =
        shortest_number(run_param(spec, decks, "x_impact_frac") * Lx / L);
    reruns.push_back(std::move(s));
  }
  return reruns;
}

std::vector<PlannedImpact> plan_campaign(const CampaignDesign& design, const Decks& decks,
                                         const std::string& out) {
  const auto index = read_campaign_index(out);
  std::map<std::string, std::string> done;
  for (const auto& e : index) done[e.id] = e.status;
  std::vector<ImpactSpec> specs = design.impacts;
  for (auto& s : end_wall_reruns(design, decks, index)) specs.push_back(std::move(s));
  std::vector<PlannedImpact> plan;
  std::map<std::string, BedFiles> beds;  // each cached bed's parameters, read once
  for (const ImpactSpec& spec : specs) {
    PlannedImpact p;
    p.id = spec.id;
    p.bed_key = bed_key(decks, bed_overrides(spec));
    p.bed_cached = bed_cached(design.cache_dir, p.bed_key);
    p.bed_building = !p.bed_cached && bed_building(design.cache_dir, p.bed_key);
    p.spec = spec_json(spec);
    if (p.bed_cached) {
      auto it = beds.find(p.bed_key);
      if (it == beds.end())
        it = beds.emplace(p.bed_key, read_bed_files(bed_prefix(design.cache_dir, p.bed_key))).first;
      p.invalid = validate_setup(spec, Shape::resolve(spec.shape), decks, it->second);
    }
    const auto d = done.find(spec.id);
    if (d != done.end()) p.status = d->second;
    plan.push_back(std::move(p));
  }
  return plan;
}

namespace {

// The world's ranks as groups of design.ranks_per_impact (one LIGGGHTS instance each); the ranks
// left over get no group (color MPI_UNDEFINED, group MPI_COMM_NULL). Collective on world.
struct Groups {
  int wrank = 0, wsize = 1, groups = 1, color = MPI_UNDEFINED, grank = -1;
  MPI_Comm group = MPI_COMM_NULL;
  Groups(const CampaignDesign& design, MPI_Comm world) {
    MPI_Comm_rank(world, &wrank);
    MPI_Comm_size(world, &wsize);
    const int k = design.ranks_per_impact;
    if (k > wsize)
      throw InputError(design.source, 0, "campaign.ranks_per_impact",
                       fmt::format("{} ranks per impact but only {} MPI ranks", k, wsize));
    groups = wsize / k;
    color = wrank < groups * k ? wrank / k : MPI_UNDEFINED;
    MPI_Comm_split(world, color, wrank, &group);
    if (group != MPI_COMM_NULL) MPI_Comm_rank(group, &grank);
  }
  ~Groups() {
    if (group != MPI_COMM_NULL) MPI_Comm_free(&group);
  }
  Groups(const Groups&) = delete;
  Groups& operator=(const Groups&) = delete;
};

// Measures `bed` on this rank alone and records it in the campaign file; a failure is said, not
// thrown (the impact is written already; `dem campaign --record-beds` measures it later).
void record_packing(const std::string& out, const BedFiles& bed) {
  try {
    record_bed_packing(out, bed.key, measure_packing(bed, MPI_COMM_SELF));
  } catch (const std::exception& e) {
    std::cerr << fmt::format("[dem] bed {}: packing not recorded: {}\n", bed.key, e.what());
  }
}

// The pending impacts of `design` (those not in options.out), in the order and on the groups of
// campaign_schedule.hpp. `planned`: the campaign's impacts in all (the progress lines'
// denominator; the reruns' pass adds them).
CampaignSummary run_pending(const CampaignDesign& design, const Decks& decks,
                            const CampaignOptions& options, MPI_Comm world, std::size_t planned) {
  const auto start = std::chrono::steady_clock::now();
  const Groups g(design, world);
  const int wrank = g.wrank, wsize = g.wsize, groups = g.groups, color = g.color, grank = g.grank;
  const MPI_Comm group = g.group;
  // LIGGGHTS's custom/vtk dump initialises VTK's MPI controller with a collective on
  // MPI_COMM_WORLD: with several instances running different impacts it waits forever.
  if (options.vtk_every > 0 && groups > 1)
    throw InputError(
        "<command line>", 0, "--vtk",
        fmt::format("VTK frames need every MPI rank in one LIGGGHTS instance (LIGGGHTS's "
                    "VTK dump synchronises all ranks): set [campaign] "
                    "ranks_per_impact = {} or run with one rank, or use "
                    "`ricochet dem impact --vtk` for one impact",
                    wsize));
  CampaignSummary summary;
  summary.groups = groups;
  // World rank 0 decides what is left to do: impacts neither in the index nor crashed.
  std::vector<int> pending;
  if (wrank == 0) {
    std::set<std::string> done;
    for (const auto& e : read_campaign_index(options.out)) done.insert(e.id);
    std::vector<std::pair<std::string, std::string>> running;
    if (fs::exists(options.out)) {
      h5::File f(options.out, h5::File::Mode::kRead);
      if (f.exists("/dem/running"))
        for (const auto& id : f.list("/dem/running"))
          running.emplace_back(id, f.attr_string("/dem/running/" + id, "work_dir"));
    }
    // An impact left "running" by a previous run: if LIGGGHTS stopped the process with an
    // error, running it again would stop this run too, so it is recorded as crashed (unless
    // --retry-crashed); if the run was killed from outside, it is simply run again.
    for (const auto& [id, dir] : running) {
      if (done.count(id)) continue;
      const auto it = std::find_if(design.impacts.begin(), design.impacts.end(),
                                   [&](const ImpactSpec& s) { return s.id == id; });
      const std::string error = last_error(dir);
      if (options.retry_crashed || error.empty() || it == design.impacts.end()) continue;
      ImpactResult r;
      r.id = id;
      r.status = "crashed";
      r.message = "LIGGGHTS stopped the previous run during this impact: " + error;
      r.work_dir = dir;
      append_result(options.out, r, *it, design.name);
      done.insert(id);
    }
    for (std::size_t i = 0; i < design.impacts.size(); ++i)
      if (!done.count(design.impacts[i].id)) pending.push_back(static_cast<int>(i));
    summary.skipped = design.impacts.size() - pending.size();
  }
  int n_pending = static_cast<int>(pending.size());
  MPI_Bcast(&n_pending, 1, MPI_INT, 0, world);
  pending.resize(static_cast<std::size_t>(n_pending));
  MPI_Bcast(pending.data(), n_pending, MPI_INT, 0, world);

  // The schedule (campaign_schedule.hpp): with several groups each takes the next impact as soon
  // as it is free, building its bed first when no one has; rank 0 looks at the cache once for the
  // order, so that every rank has the same one.
  std::vector<std::string> keys;  // the bed of each pending impact
  for (int i : pending)
    keys.push_back(bed_key(decks, bed_overrides(design.impacts[static_cast<std::size_t>(i)])));
  std::vector<char> cached(keys.size(), 0);
  if (wrank == 0)
    for (std::size_t n = 0; n < keys.size(); ++n)
      cached[n] = bed_cached(design.cache_dir, keys[n]) ? 1 : 0;
  MPI_Bcast(cached.data(), static_cast<int>(cached.size()), MPI_CHAR, 0, world);
  const std::vector<int> order = schedule_order(keys, cached, groups);
  // The bed of an impact, built first when the cache does not hold it (said by the group's rank 0).
  const auto bed_for = [&](const ImpactSpec& spec) {
    bool built = false;
    double bed_wall = 0;
    BedFiles b = ensure_bed(decks, bed_overrides(spec), design.cache_dir, group, &built, &bed_wall,
                            checkpoint_steps_of(decks, spec.params.run));
    if (grank == 0 && built)
      std::cerr << fmt::format("[dem] bed {}: {} grains built in {:.0f} s (group {})\n", b.key,
                               b.grains, bed_wall, color);
    return b;
  };
  // Pending impact n (a position into `pending`) on this group; `waits`: its bed is another
  // group's to build (claim_next).
  const auto run_one = [&](std::size_t n, bool waits) {
    const ImpactSpec& spec = design.impacts[static_cast<std::size_t>(pending[n])];
    ImpactContext ctx;
    ctx.decks = &decks;
    if (grank == 0) {
      // A line before the work (an impact on a stiff bed takes an hour, its bed longer): what
      // runs now, and whether its bed must be built first.
      std::cerr << fmt::format("[dem] starting {} (group {}), bed {}{}\n", spec.id, color, keys[n],
                               bed_cached(design.cache_dir, keys[n]) ? ""
                               : waits ? ": another group builds it, waiting for it"
                                       : ": building it first");
    }
    ctx.bed = bed_for(spec);
    ctx.extract = design.extract;
    ctx.work_dir = (fs::path(design.work_dir) / spec.id).string();
    if (options.vtk_every > 0) {
      ctx.vtk_dir = (fs::path(options.vtk_dir) / spec.id).string();
      ctx.vtk_every = options.vtk_every;
    }
    // The campaign's picture (report, upscale --figures): its first impact.
    if (options.picture && pending[n] == 0)
      ctx.picture_dir = (fs::path(ctx.work_dir) / "picture-frames").string();
    const Shape shape = Shape::resolve(spec.shape);
    ctx.template_include = ensure_template(shape, ctx.bed, design.work_dir + "/templates", group);
    ImpactProgress bar(spec.id, wrank == 0 && options.progress);
    ctx.progress = bar.callback();
    if (grank == 0) mark_running(options.out, spec.id, ctx.work_dir);
    ImpactResult r;
    try {
      r = run_impact(spec, ctx, group);
    } catch (const std::exception& e) {
      r.id = spec.id;
      r.status = "error";
      r.message = e.what();
      r.work_dir = ctx.work_dir;
    }
    bar.finish();
    ++summary.ran;
    if (grank == 0) {
      append_result(options.out, r, spec, design.name);
      if (!read_bed_packings(options.out).count(ctx.bed.key)) record_packing(options.out, ctx.bed);
      const auto total = read_campaign_index(options.out).size();
      std::cerr << fmt::format("[dem] {}/{} {} (group {}): {} in {:.0f} s, {}\n", total, planned,
                               spec.id, color, r.status, r.wall_s, r.message);
    }
  };
  if (groups == 1) {
    if (group != MPI_COMM_NULL)
      for (int n : order) run_one(static_cast<std::size_t>(n), false);
  } else {
    // The claims of this run, beside the campaign file (a killed run's are stale: emptied here).
    const std::string claims = options.out + ".claims";
    if (wrank == 0) std::ofstream(claims, std::ios::trunc);
    MPI_Barrier(world);
    while (group != MPI_COMM_NULL) {
      int next = -1;
      bool waits = false;  // read by the group's rank 0 only
      if (grank == 0) next = claim_next(claims, order, keys, design.cache_dir, &waits);
      MPI_Bcast(&next, 1, MPI_INT, 0, group);
      if (next < 0) break;
      run_one(static_cast<std::size_t>(next), waits);
    }
    MPI_Barrier(world);
    if (wrank == 0) {
      fs::remove(claims);
      fs::remove(claims + ".lock");
    }
  }
  MPI_Barrier(world);
  unsigned long ran = summary.ran;
  MPI_Allreduce(MPI_IN_PLACE, &ran, 1, MPI_UNSIGNED_LONG, MPI_SUM, world);
  summary.ran = ran;
  if (wrank == 0) {
    summary.entries = read_campaign_index(options.out);
    // A finished campaign run again rewrites its impact set, so that a file written by an
    // older version gains the newer columns (e.g. replicate) without rerunning an impact.
    if (ran == 0 && !summary.entries.empty())
      rewrite_impact_set(options.out, summary.entries, design.name);
  }
  summary.wall_s = seconds_since(start);
  return summary;
}

}  // namespace

std::vector<std::string> record_beds(const CampaignDesign& design, const Decks& decks,
                                     const std::string& out, MPI_Comm world) {
  const Groups g(design, world);
  // World rank 0 lists the beds to record, one impact of each (its overrides build the bed).
  // The file's end walls, read once by world rank 0 and told to every rank (a running campaign
  // may append meanwhile), give every rank the same reruns.
  std::vector<CampaignEntry> index;
  std::string walls;
  if (g.wrank == 0) {
    index = read_campaign_index(out);
    for (const auto& e : index)
      if (e.status == "end_wall") walls += e.id + "\n";
  }
  int length = static_cast<int>(walls.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, world);
  walls.resize(static_cast<std::size_t>(length));
  MPI_Bcast(walls.data(), length, MPI_CHAR, 0, world);
  std::vector<CampaignEntry> at_wall;
  for (std::size_t a = 0, b; (b = walls.find('\n', a)) != std::string::npos; a = b + 1) {
    CampaignEntry e;
    e.id = walls.substr(a, b - a);
    e.status = "end_wall";
    at_wall.push_back(std::move(e));
  }
  std::vector<ImpactSpec> specs = design.impacts;
  for (auto& s : end_wall_reruns(design, decks, at_wall)) specs.push_back(std::move(s));
  std::vector<int> todo;  // indices into specs
  if (g.wrank == 0) {
    std::set<std::string> ran, seen;
    for (const auto& e : index) ran.insert(e.id);
    const auto recorded = read_bed_packings(out);
    std::vector<int> rebuild;  // the cached beds first: measuring one takes seconds
    for (std::size_t i = 0; i < specs.size(); ++i) {
      if (!ran.count(specs[i].id)) continue;
      const std::string key = bed_key(decks, bed_overrides(specs[i]));
      if (recorded.count(key) || !seen.insert(key).second) continue;
      (bed_cached(design.cache_dir, key) ? todo : rebuild).push_back(static_cast<int>(i));
    }
    todo.insert(todo.end(), rebuild.begin(), rebuild.end());
  }
  int n = static_cast<int>(todo.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, world);
  todo.resize(static_cast<std::size_t>(n));
  MPI_Bcast(todo.data(), n, MPI_INT, 0, world);
  std::vector<std::string> keys;
  for (int t = 0; t < n; ++t) {
    const ImpactSpec& spec = specs.at(static_cast<std::size_t>(todo[static_cast<std::size_t>(t)]));
    const std::string key = bed_key(decks, bed_overrides(spec));
    keys.push_back(key);
    if (g.group == MPI_COMM_NULL || t % g.groups != g.color) continue;
    if (g.grank == 0)
      std::cerr << fmt::format("[dem] recording bed {} (group {}){}\n", key, g.color,
                               bed_cached(design.cache_dir, key)
                                   ? ""
                                   : ": not in the cache, building it again from its seeds");
    bool built = false;
    double wall = 0;
    const BedFiles bed = ensure_bed(decks, bed_overrides(spec), design.cache_dir, g.group, &built,
                                    &wall, checkpoint_steps_of(decks, spec.params.run));
    if (g.grank == 0) {
      if (built)
        std::cerr << fmt::format("[dem] bed {}: {} grains built in {:.0f} s (group {})\n", key,
                                 bed.grains, wall, g.color);
      record_packing(out, bed);
    }
  }
  MPI_Barrier(world);
  return keys;
}

CampaignSummary run_campaign(const CampaignDesign& design, const Decks& decks,
                             const CampaignOptions& options, MPI_Comm world) {
  CampaignSummary summary = run_pending(design, decks, options, world, design.impacts.size());
  if (!(design.end_wall_rerun_Lx_m > 0)) return summary;
  // An end wall is known only once its impact has run, so the reruns come after the design's
  // impacts. Every rank reads the index (under the file's shared lock) after run_pending's last
  // barrier: the same file, hence the same reruns on every rank.
  CampaignDesign reruns = design;
  reruns.impacts = end_wall_reruns(design, decks, read_campaign_index(options.out));
  summary.reruns = reruns.impacts.size();
  if (reruns.impacts.empty()) return summary;
  CampaignOptions o = options;
  o.picture = false;  // the campaign's picture is its design's first impact
  const CampaignSummary more =
      run_pending(reruns, decks, o, world, design.impacts.size() + reruns.impacts.size());
  summary.ran += more.ran;
  summary.skipped += more.skipped;
  summary.wall_s += more.wall_s;
  summary.entries = more.entries;
  return summary;
}

}  // namespace ricochet::dem
