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
#include "common/clock.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/progress.hpp"
#include "engine/shape.hpp"

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
    double Lx = 0;
    for (const auto& [name, value] : effective_bed(decks, spec.params.bed))
      if (name == "Lx_m") Lx = std::stod(value);
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
  for (const ImpactSpec& spec : specs) {
    PlannedImpact p;
    p.id = spec.id;
    p.bed_key = bed_key(decks, bed_overrides(spec));
    p.bed_cached = bed_cached(design.cache_dir, p.bed_key);
    p.bed_building = !p.bed_cached && bed_building(design.cache_dir, p.bed_key);
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

// The pending impacts of `design` (those not in options.out), in waves of beds. `planned`: the
// campaign's impacts in all (the progress lines' denominator; the reruns' pass adds them).
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

  // The schedule: waves of `groups` beds. In each wave every group builds one bed (each bed
  // once, by one group), then the wave's impacts are dealt round robin over the groups. A bed's
  // impacts thus come right after it: a design of many beds (the sand calibration: 20 beds of two
  // impacts, half an hour each to build at 1.5e9 Pa) writes its first impacts within the first
  // hour instead of after every bed, so a session that stops keeps impacts, not beds that a new
  // machine would have to build again. With one group each bed is built when its first impact
  // comes. Pending impacts are taken in design order within their bed, beds in the order
  // of their first pending impact. One group keeps the design's order exactly (one wave): a design
  // ordered from cheap to expensive, or the cylinder on every replica bed before the triangles
  // (stiffness-plateau.toml), stopped early has what its order put first. With several groups, the
  // pending impacts of beds the cache already holds (a session stopped mid-wave) come first, as one
  // wave with nothing to build, dealt over every group: a group whose bed was cached used to wait
  // at the wave's barrier while the other built its bed (half an hour of one core at 1.5e9 Pa).
  std::vector<std::string> wave_key;  // the wave of each pending impact (its bed key)
  std::vector<std::string> bed_order;
  for (int i : pending) {
    wave_key.push_back(
        groups == 1 ? std::string("all")
                    : bed_key(decks, bed_overrides(design.impacts[static_cast<std::size_t>(i)])));
    if (std::find(bed_order.begin(), bed_order.end(), wave_key.back()) == bed_order.end())
      bed_order.push_back(wave_key.back());
  }
  const std::size_t G = static_cast<std::size_t>(groups);
  std::vector<std::vector<std::string>> waves;
  std::vector<char> build_wave;  // whether the groups build the wave's beds before its impacts
  if (groups == 1) {
    waves.push_back(bed_order);
    build_wave.push_back(0);
  } else {
    // Rank 0 looks at the cache once and tells the others, so that every rank has one schedule.
    std::vector<char> ready(bed_order.size(), 0);
    if (wrank == 0)
      for (std::size_t b = 0; b < bed_order.size(); ++b)
        ready[b] = bed_cached(design.cache_dir, bed_order[b]) ? 1 : 0;
    MPI_Bcast(ready.data(), static_cast<int>(ready.size()), MPI_CHAR, 0, world);
    std::vector<std::string> in_cache, to_build;
    for (std::size_t b = 0; b < bed_order.size(); ++b)
      (ready[b] ? in_cache : to_build).push_back(bed_order[b]);
    if (!in_cache.empty()) {
      waves.push_back(in_cache);
      build_wave.push_back(0);
    }
    for (std::size_t w0 = 0; w0 < to_build.size(); w0 += G) {
      waves.emplace_back(
          to_build.begin() + static_cast<std::ptrdiff_t>(w0),
          to_build.begin() + static_cast<std::ptrdiff_t>(std::min(w0 + G, to_build.size())));
      build_wave.push_back(1);
    }
  }
  // The bed of an impact, built first when the cache does not hold it (said by the group's rank 0).
  const auto bed_for = [&](const ImpactSpec& spec) {
    bool built = false;
    double bed_wall = 0;
    BedFiles b = ensure_bed(decks, bed_overrides(spec), design.cache_dir, group, &built, &bed_wall);
    if (grank == 0 && built)
      std::cerr << fmt::format("[dem] bed {}: {} grains built in {:.0f} s (group {})\n", b.key,
                               b.grains, bed_wall, color);
    return b;
  };
  for (std::size_t w = 0; w < waves.size(); ++w) {
    const std::vector<std::string>& wave = waves[w];
    std::vector<int> wave_impacts;
    for (std::size_t b = 0; b < wave.size(); ++b)
      for (std::size_t n = 0; n < pending.size(); ++n)
        if (wave_key[n] == wave[b]) wave_impacts.push_back(pending[n]);
    if (build_wave[w]) {
      // Each group builds its bed of the wave before any impact runs on it.
      if (group != MPI_COMM_NULL && static_cast<std::size_t>(color) < wave.size()) {
        const auto it =
            std::find(wave_key.begin(), wave_key.end(), wave[static_cast<std::size_t>(color)]);
        const ImpactSpec& first = design.impacts[static_cast<std::size_t>(
            pending[static_cast<std::size_t>(it - wave_key.begin())])];
        (void)bed_for(first);
      }
      MPI_Barrier(world);
    }
    for (std::size_t n = 0; n < wave_impacts.size(); ++n) {
      if (group == MPI_COMM_NULL || static_cast<int>(n % G) != color) continue;
      const ImpactSpec& spec = design.impacts[static_cast<std::size_t>(wave_impacts[n])];
      ImpactContext ctx;
      ctx.decks = &decks;
      if (grank == 0) {
        // A line before the work (an impact on a stiff bed takes an hour, its bed longer): what
        // runs now, and whether its bed must be built first.
        const std::string key = bed_key(decks, bed_overrides(spec));
        std::cerr << fmt::format("[dem] starting {} (group {}), bed {}{}\n", spec.id, color, key,
                                 bed_cached(design.cache_dir, key) ? "" : ": building it first");
      }
      ctx.bed = bed_for(spec);
      ctx.extract = design.extract;
      ctx.work_dir = (fs::path(design.work_dir) / spec.id).string();
      if (options.vtk_every > 0) {
        ctx.vtk_dir = (fs::path(options.vtk_dir) / spec.id).string();
        ctx.vtk_every = options.vtk_every;
      }
      // The campaign's picture (report, upscale --figures): its first impact.
      if (options.picture && wave_impacts[n] == 0)
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
        if (!read_bed_packings(options.out).count(ctx.bed.key))
          record_packing(options.out, ctx.bed);
        const auto total = read_campaign_index(options.out).size();
        std::cerr << fmt::format("[dem] {}/{} {} (group {}): {} in {:.0f} s, {}\n", total, planned,
                                 spec.id, color, r.status, r.wall_s, r.message);
      }
    }
    MPI_Barrier(world);
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
    const BedFiles bed =
        ensure_bed(decks, bed_overrides(spec), design.cache_dir, g.group, &built, &wall);
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
