// `ricochet dem template|bed|impact|campaign`: the resolved model, sand as LIGGGHTS grains and the
// block as a multisphere body, driven through the LIGGGHTS library interface with MPI.
// See docs/commands/dem.md and docs/resolved-model.md.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bed.hpp"
#include "block_template.hpp"
#include "campaign.hpp"
#include "cli_common.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "engine/shape.hpp"
#include "impact/impact_set.hpp"
#include "impact_run.hpp"
#include "mpi_session.hpp"
#include "params.hpp"
#include "shared_options.hpp"

namespace ricochet::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct CommonOptions {
  std::string decks;
  std::vector<std::string> sets;
  std::string cache = "dem-cache";
};

void add_common(CLI::App* sub, CommonOptions& o, bool with_sets = true) {
  sub->add_option("--decks", o.decks,
                  "liggghts-inputs folder (default: $RICOCHET_LIGGGHTS_INPUTS, else "
                  "share/ricochet/liggghts-inputs beside the program)");
  if (with_sets)
    sub->add_option("--set", o.sets,
                    "Parameter override SECTION.NAME=VALUE, SECTION bed, block or run (repeatable; "
                    "names: liggghts-inputs/common/*-defaults.in, impact/setup.in)");
  sub->add_option("--cache", o.cache, "Bed cache folder (beds are keyed by their parameters)");
}

json bed_json(const dem::BedFiles& b) {
  return {{"key", b.key},
          {"prefix", b.prefix},
          {"mode", b.mode},
          {"grains", b.grains},
          {"Lx_m", b.Lx_m},
          {"Ly_m", b.Ly_m},
          {"H_m", b.H_m},
          {"z_surface_m", b.z_surface_m},
          {"dt_s", b.dt_s},
          {"settled", b.settled},
          {"settle_time_s", b.settle_time_s}};
}

json result_json(const dem::ImpactResult& r) {
  json j = {{"id", r.id},
            {"status", r.status},
            {"message", r.message},
            {"wall_s", r.wall_s},
            {"steps", r.steps},
            {"grains", r.grains},
            {"block_spheres", r.block_spheres},
            {"dt_s", r.dt_s},
            {"sim_time_s", r.sim_time_s},
            {"work_dir", r.work_dir},
            {"bed_key", r.bed_key}};
  j["cpu_s"] = r.cpu_s;
  if (r.resumed_from_s >= 0) j["resumed_from_s"] = r.resumed_from_s;
  if (r.steps > 0 && r.wall_s > 0) {
    const double grain_steps =
        static_cast<double>(r.steps) * static_cast<double>(r.grains + r.block_spheres);
    j["us_per_grain_step"] = 1e6 * r.wall_s / grain_steps;
    j["core_us_per_grain_step"] = 1e6 * r.cpu_s / grain_steps;
  }
  if (r.ok()) {
    const auto& rec = r.reconstruction;
    j["vin"] = rec.vin;
    j["vout"] = rec.vout;
    j["sigma_vin"] = rec.sigma_vin;
    j["sigma_vout"] = rec.sigma_vout;
    j["window"] = {{"method", rec.window_method},
                   {"start_s", rec.contact_start_s},
                   {"end_s", rec.contact_end_s},
                   {"points_before", rec.points_before},
                   {"points_after", rec.points_after}};
    j["force_window_s"] = {r.force_contact_start_s, r.force_contact_end_s};
    j["v_direct"] = {{"start", r.v_start_direct}, {"end", r.v_end_direct}};
    j["penetration_max_m"] = r.penetration_max_m;
    j["energy_dissipated_J"] = r.energy_dissipated_J;
    j["energy_dissipated_frac"] = r.energy_dissipated_frac;
    j["crater_depth_m"] = r.crater_depth_m;
    j["crater_width_m"] = r.crater_width_m;
  }
  return j;
}

// ------------------------------------------------------------------ template

struct TemplateOptions {
  std::string shape = "cylinder";
  double length_m = 0;
  std::string mode = "slab";
  std::string out;
  double max_radius = 0.015, tolerance = 0.0005;
  bool json = false;
};

void run_template(const TemplateOptions& o) {
  const Shape shape = Shape::resolve(o.shape);
  if (o.mode != "slab" && o.mode != "box")
    throw InputError("<command line>", 0, "--mode", "must be slab or box");
  const double length = o.length_m > 0 ? o.length_m : shape.length_m;
  dem::TemplateOptions to;
  to.max_sphere_radius_m = o.max_radius;
  to.bump_tolerance_m = o.tolerance;
  to.full_section_at_ends = o.mode == "slab";
  const auto t = dem::make_sphere_template(shape, length, to);
  dem::write_sphere_file(t, o.out + ".ms");
  // The impact deck includes PREFIX.in from its own folder: name the sphere file through
  // ${deck_dir} when the prefix is inside the deck's shapes/ folder, else by its absolute path.
  const fs::path ms = fs::absolute(o.out + ".ms");
  const std::string ref = ms.parent_path().filename() == "shapes"
                              ? "${deck_dir}/shapes/" + ms.filename().string()
                              : ms.string();
  dem::write_template_include(t, ref, o.out + ".in");
  const json j = {{"shape", shape.name},
                  {"length_m", t.length_m},
                  {"spheres", t.spheres.size()},
                  {"sphere_radius_m", t.sphere_radius_m},
                  {"spacing_m", t.spacing_m},
                  {"mass_kg", t.mass_kg},
                  {"inertia_kgm2", t.inertia_axis_kgm2},
                  {"files", {o.out + ".ms", o.out + ".in"}}};
  if (o.json)
    print_json(j);
  else
    std::cout << fmt::format(
        "{}: {} spheres of radius {} m over {} m; mass {:.4f} kg, I {:.5f} "
        "kg m^2 -> {}.ms, {}.in\n",
        shape.name, t.spheres.size(), t.sphere_radius_m, t.length_m, t.mass_kg, t.inertia_axis_kgm2,
        o.out, o.out);
}

// ------------------------------------------------------------------ bed

struct BedOptions {
  CommonOptions common;
  OutputOptions output;
  bool dry_run = false;
  std::optional<std::uint64_t> seed;  ///< replica, as a campaign's `seed` (unless bed.seed is set)
};

void run_bed_on_rank(const BedOptions& o, const MpiSession& mpi) {
  const auto decks = dem::Decks::locate(o.common.decks);
  dem::Overrides ov;
  for (const auto& s : o.common.sets) dem::apply_set_option(decks, s, ov);
  // run.checkpoint_steps sets the build's checkpoints (ensure_bed); no other run.* is a bed's.
  if (!ov.block.empty() || ov.run.size() > ov.run.count("checkpoint_steps"))
    throw InputError("<command line>", 0, "--set",
                     "a bed takes bed.* parameters and run.checkpoint_steps only");
  if (o.seed) ov.bed = dem::with_replica_seed(ov.bed, static_cast<std::int64_t>(*o.seed));
  if (o.dry_run) {
    const std::string key = dem::bed_key(decks, ov.bed);
    const std::string prefix = dem::bed_prefix(o.common.cache, key);
    const bool cached = dem::bed_cached(o.common.cache, key);
    if (mpi.rank() != 0) return;
    if (o.output.json)
      print_json({{"key", key}, {"prefix", prefix}, {"cached", cached}});
    else
      std::cout << fmt::format("bed {}: {} ({})\n", key, prefix, cached ? "cached" : "not built");
    return;
  }
  bool built = false;
  double wall = 0;
  const auto bed = dem::ensure_bed(decks, ov.bed, o.common.cache, MPI_COMM_WORLD, &built, &wall,
                                   dem::checkpoint_steps_of(decks, ov.run));
  const dem::BedPacking packing = dem::measure_packing(bed, MPI_COMM_WORLD);
  if (mpi.rank() != 0) return;
  json j = bed_json(bed);
  j["built"] = built;
  j["wall_s"] = wall;
  j["ranks"] = mpi.size();
  j["grain_volume_m3"] = packing.grain_volume_m3;
  j["solid_fraction"] = packing.solid_fraction;
  j["bulk_density_kg_m3"] = packing.bulk_density_kg_m3;
  if (o.output.json)
    print_json(j);
  else
    std::cout << fmt::format(
        "bed {} ({}): {} grains, surface at {:.4f} m, solid fraction {:.3f} (bulk density {:.0f} "
        "kg/m^3), dt {:.3g} s, {}{}\n",
        bed.key, bed.mode, bed.grains, bed.z_surface_m, packing.solid_fraction,
        packing.bulk_density_kg_m3, bed.dt_s,
        built ? fmt::format("built in {:.0f} s", wall) : "from the cache",
        bed.settled ? "" : " -- NOT SETTLED");
}

void run_bed(const BedOptions& o) {
  MpiSession mpi;
  mpi.run([&] { run_bed_on_rank(o, mpi); });
}

// ------------------------------------------------------------------ impact

// --vtk DIR and --vtk-every N of `dem impact` and `dem campaign` (docs/paraview.md).
void add_vtk_options(CLI::App* sub, std::string& dir, long& every, const std::string& where = "") {
  sub->add_option("--vtk", dir,
                  "Write ParaView files of the grains and the block (grains_STEP.vtk, "
                  "block_STEP.vtk) into DIR" +
                      where);
  sub->add_option("--vtk-every", every, "Steps between ParaView frames (with --vtk)")
      ->capture_default_str();
  check_range(sub, "--vtk-every", 1, 1e9);
}

struct ImpactOptions {
  CommonOptions common;
  OutputOptions output;
  // The library's defaults (impact_spec.hpp), which --help shows.
  std::string shape = dem::ImpactSpec{}.shape;
  std::string vin = format_vin(dem::ImpactSpec{}.vin);
  double alpha_deg = 0;
  std::optional<std::uint64_t> seed;
  std::string id = "impact";
  std::string work = "dem-work";
  double fps = dem::ExtractOptions{}.fps;
  std::string window;
  std::string vtk;
  long vtk_every = dem::kDefaultVtkEvery;
};

// --out: a .csv impact set of this one rebound, or the impact appended to a campaign file.
void write_impact(const std::string& out, const dem::ImpactResult& r, const dem::ImpactSpec& spec) {
  if (out.ends_with(".csv")) {
    if (!r.ok())
      throw InputError(
          out, 0, "--out",
          "impact " + r.status + ": no rebound to write as an impact set (" + r.message + ")");
    ImpactSet set;
    set.source = "ricochet dem impact";
    set.extra_names = dem::impact_extra_names();
    set.extra_units = dem::impact_extra_units();
    set.impacts = {r.impact};
    write_impact_set_csv(set, out);
  } else {
    dem::append_result(out, r, spec, "dem impact");
  }
}

void print_impact_text(const dem::ImpactResult& r, int ranks) {
  std::cout << fmt::format("{}: {} ({}) in {:.0f} s, {} steps, {} grains on {} rank(s)\n", r.id,
                           r.status, r.message, r.wall_s, r.steps, r.grains, ranks);
  if (r.ok())
    std::cout << fmt::format(
        "  V_in = ({:.3f}, {:.3f}, {:.2f})  V_out = ({:.3f}, {:.3f}, {:.2f})  (m/s, m/s, "
        "rad/s)\n  penetration {:.4f} m, contact {:.4f} s, energy dissipated {:.1f} J ({:.0f} "
        "%), crater {:.3f} m deep x {:.3f} m wide\n",
        r.impact.vin[0], r.impact.vin[1], r.impact.vin[2], r.impact.vout[0], r.impact.vout[1],
        r.impact.vout[2], r.penetration_max_m, r.impact.contact_duration.value_or(0),
        r.energy_dissipated_J, 100 * r.energy_dissipated_frac, r.crater_depth_m, r.crater_width_m);
}

void run_impact_command_on_rank(const ImpactOptions& o, const MpiSession& mpi) {
  dem::ImpactSpec spec;
  spec.vin = parse_vin(o.vin);
  const auto decks = dem::Decks::locate(o.common.decks);
  spec.id = o.id;
  spec.shape = o.shape;
  (void)Shape::resolve(o.shape);
  spec.alpha_in_rad = o.alpha_deg * std::numbers::pi / 180.0;
  if (o.seed) spec.seed = static_cast<std::int64_t>(*o.seed);
  for (const auto& s : o.common.sets) dem::apply_set_option(decks, s, spec.params);
  if (!o.output.out.empty()) {
    require_out_extension(o.output, {".h5", ".hdf5", ".csv"});
    if (!o.output.out.ends_with(".csv"))
      for (const auto& e : dem::read_campaign_index(o.output.out))
        if (e.id == o.id)
          throw InputError(o.output.out, 0, "--id",
                           "impact '" + o.id + "' is already in the file: choose another --id");
  }
  if (!o.window.empty() && o.window != "ground" && o.window != "force" && o.window != "auto")
    throw InputError("<command line>", 0, "--window", "must be ground, force or auto");

  dem::ImpactContext ctx;
  ctx.decks = &decks;
  ctx.extract.fps = o.fps;
  ctx.extract.window = o.window;
  if (!o.vtk.empty()) {
    ctx.vtk_dir = o.vtk;
    ctx.vtk_every = o.vtk_every;
  }
  // A campaign file gets the impact's picture (/dem/snapshot).
  if (!o.output.out.empty() && !o.output.out.ends_with(".csv"))
    ctx.picture_dir = (std::filesystem::path(o.work) / (o.id + "-picture-frames")).string();
  bool built = false;
  double bed_wall = 0;
  ctx.bed = dem::ensure_bed(decks, dem::bed_overrides(spec), o.common.cache, MPI_COMM_WORLD, &built,
                            &bed_wall, dem::checkpoint_steps_of(decks, spec.params.run));
  const Shape shape = Shape::resolve(spec.shape);
  ctx.template_include =
      dem::ensure_template(shape, ctx.bed, o.work + "/templates", MPI_COMM_WORLD);
  ctx.work_dir = (fs::path(o.work) / spec.id).string();
  dem::ImpactProgress bar(spec.id, mpi.rank() == 0 && !o.output.json);
  ctx.progress = bar.callback();
  const auto r = dem::run_impact(spec, ctx, MPI_COMM_WORLD);
  bar.finish();
  if (mpi.rank() != 0) return;
  if (!o.output.out.empty()) write_impact(o.output.out, r, spec);
  json j = result_json(r);
  j["bed"] = bed_json(ctx.bed);
  j["bed"]["built"] = built;
  j["ranks"] = mpi.size();
  if (o.output.json)
    print_json(j);
  else
    print_impact_text(r, mpi.size());
}

void run_impact_command(const ImpactOptions& o) {
  MpiSession mpi;
  mpi.run([&] { run_impact_command_on_rank(o, mpi); });
}

// ------------------------------------------------------------------ campaign

struct CampaignOptions {
  std::string design;
  std::string decks;
  bool retry = false;
  OutputOptions output;
  std::string vtk;
  long vtk_every = dem::kDefaultVtkEvery;
  bool no_picture = false;
  bool dry_run = false;
  bool record_beds = false;
  std::vector<std::string> only;    ///< empty: every impact of the design
  std::vector<std::string> forget;  ///< impacts to remove from --out (run again next time)
};

// --dry-run: what a run would do (dem::plan_campaign), printed by rank 0; nothing runs.
void print_campaign_plan(const CampaignOptions& o, const dem::CampaignDesign& design,
                         const dem::Decks& decks) {
  const auto plan = dem::plan_campaign(design, decks, o.output.out);
  std::set<std::string> beds, to_build;
  std::size_t to_run = 0, refused = 0;
  for (const auto& p : plan) {
    beds.insert(p.bed_key);
    if (!p.status.empty()) continue;
    ++to_run;
    if (!p.invalid.empty()) ++refused;
    if (!p.bed_cached) to_build.insert(p.bed_key);
  }
  if (o.output.json) {
    json list = json::array();
    for (const auto& p : plan)
      list.push_back({{"id", p.id},
                      {"bed_key", p.bed_key},
                      {"bed_cached", p.bed_cached},
                      {"bed_building", p.bed_building},
                      {"status", p.status.empty() ? json(nullptr) : json(p.status)},
                      {"invalid", p.invalid.empty() ? json(nullptr) : json(p.invalid)},
                      {"spec", json::parse(p.spec)}});
    print_json({{"design", design.source},
                {"name", design.name},
                {"out", o.output.out},
                {"cache_dir", design.cache_dir},
                {"impacts", list},
                {"beds", beds.size()},
                {"to_run", to_run},
                {"to_run_invalid", refused},
                {"beds_to_build", to_build.size()}});
    return;
  }
  std::cout << fmt::format("campaign {} ({}): {} impacts on {} beds, cache {}\n", design.name,
                           design.source, plan.size(), beds.size(), design.cache_dir);
  for (const auto& p : plan)
    std::cout << fmt::format("  {:<40} bed {} {:<10} {}\n", p.id, p.bed_key,
                             p.bed_cached     ? "cached"
                             : p.bed_building ? "building"
                                              : "to build",
                             p.status.empty() ? "to run" : p.status);
  for (const auto& p : plan)
    if (p.status.empty() && !p.invalid.empty())
      std::cout << fmt::format("  {}: would be refused (invalid): {}\n", p.id, p.invalid);
  std::cout << fmt::format(
      "to run: {} impact{}, {} bed{} to build{}\n", to_run, to_run == 1 ? "" : "s", to_build.size(),
      to_build.size() == 1 ? "" : "s",
      o.output.out.empty() ? " (no --out: every impact counted as to run)" : "");
}

void run_campaign_command_on_rank(const CampaignOptions& o, const MpiSession& mpi) {
  const auto decks = dem::Decks::locate(o.decks);
  auto design = dem::read_campaign_design(o.design, decks);
  if (!o.only.empty()) design = dem::select_impacts(std::move(design), o.only);
  if (o.dry_run) {
    if (mpi.rank() == 0) print_campaign_plan(o, design, decks);
    return;
  }
  if (o.output.out.empty())
    throw InputError("<command line>", 0, "--out", "a campaign needs --out FILE.h5 (resumable)");
  require_extension("--out", o.output.out, {".h5", ".hdf5"});
  if (!o.forget.empty()) {
    // Only on world rank 0: the file's lock serialises the writers, not the ranks of one run.
    if (mpi.rank() != 0) return;
    for (const std::string& id : o.forget)
      if (std::none_of(design.impacts.begin(), design.impacts.end(),
                       [&](const dem::ImpactSpec& s) { return s.id == id; }))
        throw InputError("<command line>", 0, "--forget",
                         fmt::format("'{}' is not an impact of {}", id, design.source));
    const auto gone = dem::forget_impacts(o.output.out, o.forget);
    if (o.output.json) {
      json list = json::array();
      for (const auto& e : gone)
        list.push_back({{"id", e.id}, {"status", e.status}, {"message", e.message}});
      print_json({{"design", design.source}, {"out", o.output.out}, {"forgotten", list}});
      return;
    }
    for (const auto& e : gone)
      std::cout << fmt::format("forgot {} ({}{}{}): it runs again with the design\n", e.id,
                               e.status, e.message.empty() ? "" : ": ", e.message);
    return;
  }
  if (o.record_beds) {
    if (!std::filesystem::exists(o.output.out))
      throw InputError(o.output.out, 0, "--record-beds", "no campaign file: nothing to record");
    const auto keys = dem::record_beds(design, decks, o.output.out, MPI_COMM_WORLD);
    if (mpi.rank() != 0) return;
    std::map<std::string, double> phi;
    for (const auto& [key, p] : dem::read_bed_packings(o.output.out)) phi[key] = p.solid_fraction;
    if (o.output.json) {
      print_json({{"design", design.source},
                  {"out", o.output.out},
                  {"recorded_now", keys},
                  {"solid_fraction", phi}});
      return;
    }
    std::cout << fmt::format("campaign {}: {} bed(s) recorded now, {} in the file\n", design.name,
                             keys.size(), phi.size());
    for (const auto& [key, f] : phi)
      std::cout << fmt::format("  bed {}  solid fraction {:.4f}\n", key, f);
    return;
  }
  dem::CampaignOptions co;
  co.out = o.output.out;
  co.retry_crashed = o.retry;
  if (!o.vtk.empty()) {
    co.vtk_dir = o.vtk;
    co.vtk_every = o.vtk_every;
  }
  co.picture = !o.no_picture;
  co.progress = !o.output.json;
  const auto s = dem::run_campaign(design, decks, co, MPI_COMM_WORLD);
  if (mpi.rank() != 0) return;
  std::map<std::string, int> counts;
  for (const auto& e : s.entries) ++counts[e.status];
  json j = {{"design", design.source},
            {"name", design.name},
            {"out", co.out},
            {"impacts", design.impacts.size()},
            {"ran", s.ran},
            {"skipped_already_done", s.skipped},
            {"end_wall_reruns", s.reruns},
            {"groups", s.groups},
            {"ranks", mpi.size()},
            {"ranks_per_impact", design.ranks_per_impact},
            {"wall_s", s.wall_s},
            {"status_counts", counts}};
  json list = json::array();
  const auto& names = dem::campaign_value_names();
  for (const auto& e : s.entries) {
    json x = {{"id", e.id}, {"status", e.status}, {"message", e.message}};
    for (std::size_t c = 0; c < names.size() && c < e.values.size(); ++c)
      if (std::isfinite(e.values[c])) x[names[c]] = e.values[c];
    list.push_back(x);
  }
  j["results"] = list;
  if (o.output.json) {
    print_json(j);
  } else {
    std::cout << fmt::format(
        "campaign {}: {} impacts{}, {} run now, {} already done, {} group(s) of "
        "{} rank(s), {:.0f} s\n",
        design.name, design.impacts.size(),
        s.reruns ? fmt::format(" and {} end-wall rerun(s)", s.reruns) : std::string(), s.ran,
        s.skipped, s.groups, design.ranks_per_impact, s.wall_s);
    for (const auto& [status, n] : counts) std::cout << fmt::format("  {:>18}: {}\n", status, n);
    std::cout << "results: " << co.out << " (/impacts, /dem/index, /dem/tracks)\n";
  }
}

void run_campaign_command(const CampaignOptions& o) {
  MpiSession mpi;
  mpi.run([&] { run_campaign_command_on_rank(o, mpi); });
}

}  // namespace

void add_dem_command(CLI::App& app) {
  auto* dem = app.add_subcommand(
      "dem", "Resolved model: LIGGGHTS sand bed + multisphere block (docs/commands/dem.md)");
  dem->require_subcommand(1);

  auto tpl = std::make_shared<TemplateOptions>();
  auto* t = dem->add_subcommand("template", "Generate a block's multisphere template for a deck");
  t->add_option("--shape", tpl->shape, "cylinder, triangle or a shape file (.toml)");
  t->add_option("--length", tpl->length_m,
                "Modelled length [m] (slab width; default: the block's)");
  t->add_option("--mode", tpl->mode, "slab (full section at the ends) or box (rounded ends)");
  t->add_option("--max-sphere-radius", tpl->max_radius, "Largest template sphere radius [m]");
  t->add_option("--tolerance", tpl->tolerance, "Largest bump between spheres [m]");
  t->add_option("--out", tpl->out, "Output prefix: writes PREFIX.ms and PREFIX.in")->required();
  t->add_flag("--json", tpl->json, "Print one machine-readable JSON document on stdout");
  check_range(t, "--length", 1e-3, 100);
  check_range(t, "--max-sphere-radius", 1e-5, 10);
  check_range(t, "--tolerance", 1e-7, 1);
  t->callback([tpl] { run_template(*tpl); });

  auto bed = std::make_shared<BedOptions>();
  auto* b = dem->add_subcommand("bed", "Build (or reuse from the cache) a settled bed");
  add_common(b, bed->common);
  b->add_flag("--json", bed->output.json, "Print one machine-readable JSON document on stdout");
  b->add_flag("--dry-run", bed->dry_run, "Print the bed's cache key and whether it is cached");
  add_seed_option(b, bed->seed,
                  "the replica: the bed of a campaign impact with this `seed` (default: the "
                  "decks' bed seed)");
  b->callback([bed] { run_bed(*bed); });

  auto imp = std::make_shared<ImpactOptions>();
  auto* i = dem->add_subcommand("impact", "Run one resolved impact on all MPI ranks");
  add_common(i, imp->common);
  add_output_options(i, imp->output);
  i->add_option("--shape", imp->shape, "cylinder, triangle or a shape file (.toml)")
      ->capture_default_str();
  add_vin_option(i, imp->vin, "Incident state at first contact, paper frame")
      ->capture_default_str();
  i->add_option("--alpha-deg", imp->alpha_deg, "Incident orientation [deg]");
  add_seed_option(i, imp->seed, "the replica: bed and insertion seeds (default: the decks')");
  i->add_option("--id", imp->id, "Impact id (work folder name)");
  i->add_option("--work", imp->work, "Work folder (per-impact logs and tracks)");
  i->add_option("--fps", imp->fps, "Frame rate given to the reconstruction (0 = every record)")
      ->capture_default_str();
  i->add_option(
      "--window", imp->window,
      "Contact window: force (default, DEM contact force), ground (paper Fig. 8b) or auto "
      "(ballistic residuals)");
  add_vtk_options(i, imp->vtk, imp->vtk_every);
  check_range(i, "--alpha-deg", -360, 360);
  check_range(i, "--fps", 0, 1e7);
  i->callback([imp] { run_impact_command(*imp); });

  auto camp = std::make_shared<CampaignOptions>();
  auto* c = dem->add_subcommand("campaign", "Run a design of impacts over MPI ranks (resumable)");
  c->add_option("design", camp->design, "Design file (.toml)")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("--decks", camp->decks, "liggghts-inputs folder");
  c->add_flag("--retry-crashed", camp->retry, "Rerun impacts that were running when a run died");
  add_output_options(c, camp->output, JsonOut::kRefused);
  add_vtk_options(c, camp->vtk, camp->vtk_every, " (one folder per impact: DIR/ID/)");
  c->add_flag(
      "--dry-run", camp->dry_run,
      "Run nothing: list each impact's bed (cached, building or to build) and whether --out FILE "
      "already has it");
  c->add_option("--only", camp->only,
                "Run (or list) only these impacts of the design, by id, comma-separated, in the "
                "design's order (their end-wall reruns included)")
      ->delimiter(',');
  c->add_option("--forget", camp->forget,
                "Run nothing: remove these impacts (by id, comma-separated) from --out FILE, "
                "their index rows and tracks, so that the next run of the design runs them again "
                "(the repair of a record a fault wrote)")
      ->delimiter(',');
  c->add_flag("--record-beds", camp->record_beds,
              "Run no impact: record in --out FILE the packing of every bed it has impacts on and "
              "does not record yet (measured on the cached bed, or on the bed built again from "
              "its seeds), for calibrate-grains' --solid-fraction");
  c->add_flag("--no-picture", camp->no_picture,
              "Do not store the picture of the first impact (/dem/snapshot; drawn by report and "
              "upscale --figures)");
  c->callback([camp] { run_campaign_command(*camp); });

  add_dem_drop_command(*dem);    // cmd_dem_drop.cpp
  add_dem_repose_command(*dem);  // cmd_dem_drop.cpp
}

}  // namespace ricochet::cli
