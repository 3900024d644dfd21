#include "impact_run.hpp"

#include "common/clock.hpp"
#include "common/nan.hpp"
#include "frames.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "block_template.hpp"
#include "chunk_run.hpp"
#include "impact_checkpoint.hpp"
#include "impact_extract.hpp"
#include "liggghts.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

double run_param(const ImpactSpec& spec, const Decks& decks, const std::string& name) {
  return run_param(decks, spec.params.run, name);
}

namespace {

// Atom type of the block's spheres (impact/setup.in: `group block type 2`, common/materials.in).
constexpr int kBlockAtomType = 2;

// Bed tops along x: bins of width bin_m over [0, Lx); per bin the mean of z + r over the grains
// whose top is within 2 r_max of the bin's highest top (the top layer), NaN for an empty bin.
std::vector<double> profile_from(const Liggghts::LocalAtoms& atoms, const BedFiles& bed,
                                 double bin_m, MPI_Comm comm) {
  const auto n = static_cast<std::size_t>(std::ceil(bed.Lx_m / bin_m));
  std::vector<double> top(n, -1e30), sum(n, 0.0), count(n, 0.0);
  auto bin_of = [&](double x) {
    const auto b = static_cast<long>(std::floor(x / bin_m));
    return static_cast<std::size_t>(std::clamp<long>(b, 0, static_cast<long>(n) - 1));
  };
  for (std::size_t i = 0; i < atoms.x.size(); ++i)
    if (atoms.type[i] == 1)
      top[bin_of(atoms.x[i][0])] =
          std::max(top[bin_of(atoms.x[i][0])], atoms.x[i][2] + atoms.radius[i]);
  MPI_Allreduce(MPI_IN_PLACE, top.data(), static_cast<int>(n), MPI_DOUBLE, MPI_MAX, comm);
  for (std::size_t i = 0; i < atoms.x.size(); ++i) {
    if (atoms.type[i] != 1) continue;
    const auto b = bin_of(atoms.x[i][0]);
    const double z = atoms.x[i][2] + atoms.radius[i];
    if (z > top[b] - 2 * bed.r_max_m) {
      sum[b] += z;
      count[b] += 1;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sum.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, count.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, comm);
  std::vector<double> profile(n, kNaN);
  for (std::size_t b = 0; b < n; ++b)
    if (count[b] > 0) profile[b] = sum[b] / count[b];
  return profile;
}

double process_cpu_s() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace

std::map<std::string, std::string> bed_overrides(const ImpactSpec& spec) {
  return with_replica_seed(spec.params.bed, spec.seed);
}

std::string ensure_template(const Shape& shape, const BedFiles& bed, const std::string& dir) {
  const bool slab = bed.mode == "slab";
  const double length = slab ? bed.Ly_m : shape.length_m;
  TemplateOptions options;
  options.full_section_at_ends = slab;
  const SphereTemplate t = make_sphere_template(shape, length, options);
  fs::create_directories(dir);
  const std::string base =
      (fs::path(dir) / fmt::format("{}_{}_L{}", shape.name, bed.mode, shortest_number(length)))
          .string();
  if (!fs::exists(base + ".in")) {
    const std::string tmp = fmt::format("{}.tmp{}", base, static_cast<long>(::getpid()));
    write_sphere_file(t, tmp + ".ms");
    fs::rename(tmp + ".ms", base + ".ms");
    write_template_include(t, base + ".ms", tmp + ".in");
    fs::rename(tmp + ".in", base + ".in");
  }
  return base + ".in";
}

std::string ensure_template(const Shape& shape, const BedFiles& bed, const std::string& dir,
                            MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string include;
  if (rank == 0) include = ensure_template(shape, bed, dir);
  MPI_Barrier(comm);
  if (rank != 0) include = ensure_template(shape, bed, dir);
  return include;
}

ImpactProgress::ImpactProgress(const std::string& id, bool shown) {
  if (shown) bar_ = std::make_unique<Progress>("dem " + id, 1000, true);
}

ImpactProgress::~ImpactProgress() = default;

std::function<void(double, double)> ImpactProgress::callback() {
  return [this](double t, double t_max) {
    if (!bar_) return;
    const auto now = static_cast<std::size_t>(std::clamp(1000.0 * t / t_max, 0.0, 1000.0));
    if (now > shown_) bar_->advance(now - shown_);
    shown_ = std::max(shown_, now);
  };
}

void ImpactProgress::finish() {
  if (bar_) bar_->finish();
}

std::string validate_setup(const ImpactSpec& spec, const Shape& shape, const Decks& decks,
                           const BedFiles& bed) {
  if (!(spec.vin[kVy] < 0))
    return fmt::format("incident vy = {} m/s: the block must move downwards (vy < 0)",
                       spec.vin[kVy]);
  for (double v : spec.vin)
    if (!std::isfinite(v)) return "incident state is not finite";
  if (bed.mode == "box" && shape.length_m > bed.Ly_m)
    return fmt::format("block length {} m does not fit the {} m wide box", shape.length_m,
                       bed.Ly_m);
  const double frac = run_param(spec, decks, "x_impact_frac");
  const double t_pre = run_param(spec, decks, "t_pre_s");
  // Same margins as the deck's end_wall criterion (setup.in: x_wall_front, x_wall_back).
  const double front = 2 * shape.bounding_radius() + 4 * bed.r_max_m;
  const double back = shape.bounding_radius() + 4 * bed.r_max_m;
  const double x_contact = frac * bed.Lx_m;
  const double x_ins = x_contact - spec.vin[kVx] * t_pre;
  if (x_ins < back || x_contact > bed.Lx_m - front)
    return fmt::format(
        "the block would start at x = {:.3f} m and touch the bed at x = {:.3f} m: it must start "
        "at least {:.3f} m from the wall behind it and touch at least {:.3f} m before the wall "
        "ahead (bounding radius + 4 grain radii, twice the bounding radius ahead) of the {} m bed",
        x_ins, x_contact, back, front, bed.Lx_m);
  const double drop = -spec.vin[kVy] * t_pre - 0.5 * kDeckGravity_mps2 * t_pre * t_pre;
  const double y_ins = bed.z_surface_m + shape.depth_below_centroid(spec.alpha_in_rad) + drop;
  if (y_ins + shape.bounding_radius() > bed.z_box_top_m)
    return fmt::format(
        "the block would be inserted at y = {:.3f} m, its top above the box top {:.3f} m "
        "(shorten t_pre_s or raise the bed's headroom_m)",
        y_ins, bed.z_box_top_m);
  return "";
}

std::vector<double> surface_profile(Liggghts& lmp, const BedFiles& bed, double bin_m) {
  return profile_from(lmp.local_atoms(), bed, bin_m, lmp.comm());
}

namespace {

// The result's identity before anything runs: the impact, the bed, its parameters.
ImpactResult start_result(const ImpactSpec& spec, const ImpactContext& ctx) {
  const Decks& decks = *ctx.decks;
  const BedFiles& bed = ctx.bed;
  ImpactResult r;
  r.id = spec.id;
  r.bed_key = bed.key;
  r.grains = bed.grains;
  r.dt_s = bed.dt_s;
  r.work_dir = ctx.work_dir;
  for (const auto& p : decks.bed_params)
    if (const auto it = bed.values.find(p.name); it != bed.values.end())
      r.bed_values[p.name] = it->second;
  for (const auto& p : decks.block_params) {
    const auto it = spec.params.block.find(p.name);
    r.block_values[p.name] = it == spec.params.block.end() ? p.default_value : it->second;
  }
  return r;
}

// The impact deck's variables: decks, bed, output prefix, the incident state, the overrides, the
// replica's block seed, and the dump folders (created before any rank opens them).
std::vector<std::pair<std::string, std::string>> deck_variables(const ImpactSpec& spec,
                                                                const ImpactContext& ctx,
                                                                const Shape& shape,
                                                                const std::string& out, int rank,
                                                                MPI_Comm comm) {
  const Decks& decks = *ctx.decks;
  std::vector<std::pair<std::string, std::string>> vars = {
      {"deck_dir", decks.impact_dir},
      {"common", decks.common},
      {"bed", ctx.bed.prefix},
      {"template_in", ctx.template_include},
      {"out", out},
      {"shape", shape.name},
      {"vx_in_mps", shortest_number(spec.vin[kVx])},
      {"vy_in_mps", shortest_number(spec.vin[kVy])},
      {"w_in_radps", shortest_number(spec.vin[kW])},
      {"alpha_in_deg", shortest_number(spec.alpha_in_rad * 180.0 / std::numbers::pi)}};
  for (const auto& [k, v] : spec.params.block) vars.emplace_back(k, v);
  for (const auto& [k, v] : spec.params.run) vars.emplace_back(k, v);
  if (spec.seed && !spec.params.run.count("block_seed"))
    vars.emplace_back("block_seed", std::to_string(liggghts_seed(*spec.seed, 1)));
  const auto dump_into = [&](const std::string& dir, const char* prefix, long every) {
    const std::string abs = fs::absolute(dir).string();
    if (rank == 0) fs::create_directories(abs);
    MPI_Barrier(comm);
    vars.emplace_back(std::string(prefix) + "_dir", abs);
    vars.emplace_back(std::string(prefix) + "_every", std::to_string(every));
  };
  if (ctx.vtk_every > 0) dump_into(ctx.vtk_dir, "vtk", ctx.vtk_every);
  if (!ctx.picture_dir.empty()) dump_into(ctx.picture_dir, "pic", kDefaultVtkEvery);
  return vars;
}

// The impact itself: the deck's set-up, the run in chunks under the driver's checks, and the
// deck's finish; status, steps and times into r. With checkpoint_steps > 0 the run writes a
// checkpoint every that many steps and, started again in the same work folder after a kill,
// resumes from the last one (impact_checkpoint.hpp).
Simulated simulate(const ImpactContext& ctx, std::vector<std::pair<std::string, std::string>> vars,
                   double crater_bin, ImpactResult& r, MPI_Comm comm) {
  const Decks& decks = *ctx.decks;
  const BedFiles& bed = ctx.bed;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Simulated sim;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_s();
  const std::string work = ctx.work_dir;
  const std::string out = (fs::path(work) / "impact").string();
  const std::string fingerprint = checkpoint_fingerprint(vars, decks);
  // Rank 0 reads the work folder's checkpoint and tells the instance's other ranks.
  std::string text;
  if (rank == 0) {
    if (const auto c = read_checkpoint(work, fingerprint)) {
      text = checkpoint_to_json(*c);
      // The track's rows after the checkpoint come again; the logs of the earlier segment stay.
      fs::resize_file(out + ".track.txt", c->track_bytes);
      for (const char* f : {"log.liggghts", "screen.txt"}) {
        std::error_code ec;
        fs::rename(fs::path(work) / f, fs::path(work) / fmt::format("{}.{}", f, c->generation), ec);
      }
    } else {
      remove_checkpoints(work);  // none, or another impact's: start afresh
    }
  }
  int n = static_cast<int>(text.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, comm);
  text.resize(static_cast<std::size_t>(n));
  MPI_Bcast(text.data(), n, MPI_CHAR, 0, comm);
  std::optional<ImpactCheckpoint> resumed;
  if (!text.empty()) {
    resumed = checkpoint_from_json(text);
    for (auto& v : resume_variables(*resumed, work)) vars.push_back(std::move(v));
    sim.resumed_from_s = resumed->t_s;
    sim.earlier_wall_s = resumed->wall_s;
    sim.earlier_cpu_s = resumed->cpu_s;
    if (rank == 0)
      std::cerr << fmt::format("[dem] {}: resuming from its checkpoint at t = {:.4f} s (step {})\n",
                               r.id, resumed->t_s, resumed->step - resumed->first_step);
  }
  vars.emplace_back("checkpoint_prefix", checkpoint_new_prefix(work));

  Liggghts lmp(comm, (fs::path(work) / "log.liggghts").string(),
               (fs::path(work) / "screen.txt").string(), vars);
  lmp.file(decks.impact_dir + "/setup.in");
  lmp.set_time_origin(static_cast<long>(lmp.number("step0").value_or(0)));
  r.block_spheres = static_cast<long>(lmp.number("block_nspheres").value_or(0));
  r.dt_s = lmp.timestep_s();
  // The restart carries the bed's step count on: count the impact's own steps, from the step
  // after the block's insertion.
  const long first_step = resumed ? resumed->first_step : lmp.step();
  sim.block_mass = lmp.number("block_mass_kg").value_or(0);
  if (sim.block_mass > 0) r.block_mass_kg = sim.block_mass;
  sim.t_max = lmp.number("t_max_s").value_or(0);
  const long chunk = static_cast<long>(lmp.number("chunk_steps").value_or(100));
  const long expected = bed.grains + r.block_spheres;
  // The grains group is fixed at set-up and loses the atoms that leave the box: the rest of the
  // atoms are the block's spheres.
  const auto grains_now = [&] { return static_cast<long>(lmp.number("grain_atoms").value_or(0)); };
  const auto atoms_lost = [&](double t) -> std::string {
    const long lost =
        acceptable_grain_loss(lmp.natoms(), grains_now(), bed.grains, r.block_spheres);
    if (lost < 0)
      return fmt::format(
          "{} atoms at t = {:.4f} s, expected {} ({} of {} block spheres): grains or the "
          "block left the box (time step too large?)",
          lmp.natoms(), t, expected, lmp.natoms() - grains_now(), r.block_spheres);
    r.grains_lost = lost;
    return "";
  };
  if (!block_inserted(lmp.natoms(), resumed ? grains_now() : bed.grains, bed.grains,
                      r.block_spheres, resumed.has_value())) {
    r.status = "not_inserted";
    r.message = fmt::format("{} atoms after the block insertion, expected {} grains + {} spheres",
                            lmp.natoms(), bed.grains, r.block_spheres);
  } else {
    sim.before = resumed ? resumed->surface_before_m : surface_profile(lmp, bed, crater_bin);
    // The grains' largest overlap at every record (the deck cannot compute it: its compute
    // pair/gran/local must exist before the bed's first run).
    lmp.start_overlap_probe(static_cast<long>(lmp.number("record_every").value_or(10)),
                            kBlockAtomType);
    if (resumed) lmp.preload_overlap_steps(resumed->overlaps);
    ChunkRun run;
    run.chunk_steps = chunk;
    run.check_file = decks.impact_dir + "/check.in";
    run.done_variable = "impact_done";
    run.body = "block";
    run.state_variables = {"bx", "by", "bvx", "bvy", "bw"};
    run.expected_atoms = expected;
    run.atoms_lost = atoms_lost;
    if (ctx.progress) run.progress = [&](double t) { ctx.progress(t, sim.t_max); };
    run.checkpoint_every_steps = static_cast<long>(lmp.number("checkpoint_steps").value_or(0));
    run.checkpoint_from_step = first_step;
    long generation = resumed ? resumed->generation : 0;
    run.checkpoint = [&](const ChunkOutcome& so_far) {
      lmp.file(decks.impact_dir + "/checkpoint.in");
      ImpactCheckpoint c;
      c.fingerprint = fingerprint;
      c.generation = ++generation;
      c.step0 = static_cast<long>(lmp.number("step0").value_or(0));
      c.first_step = first_step;
      c.step = lmp.step();
      c.t_s = lmp.time_s();
      c.rayleigh_fraction =
          std::max(so_far.rayleigh_fraction, resumed ? resumed->rayleigh_fraction : 0.0);
      c.hertz_fraction = std::max(so_far.hertz_fraction, resumed ? resumed->hertz_fraction : 0.0);
      c.surface_before_m = sim.before;
      for (const auto& name : kDeckState)
        c.deck_state.emplace_back(name, lmp.string(name).value_or(""));
      c.overlaps = lmp.overlap_steps();
      c.cpu_s = process_cpu_s() - cpu_start;
      MPI_Allreduce(MPI_IN_PLACE, &c.cpu_s, 1, MPI_DOUBLE, MPI_SUM, comm);
      c.cpu_s += sim.earlier_cpu_s;
      c.wall_s = seconds_since(start) + sim.earlier_wall_s;
      if (rank == 0) {
        c.track_bytes = fs::file_size(out + ".track.txt");
        commit_checkpoint(work, c);
      }
      MPI_Barrier(comm);
    };
    const ChunkOutcome outcome = run_chunks(lmp, run);
    sim.overlaps = lmp.overlap_samples();
    r.status = outcome.status;
    r.message = outcome.message;
    r.rayleigh_fraction =
        std::max(outcome.rayleigh_fraction, resumed ? resumed->rayleigh_fraction : 0.0);
    r.hertz_fraction = std::max(outcome.hertz_fraction, resumed ? resumed->hertz_fraction : 0.0);
    // After a failure found by the driver the block state may be gone or meaningless: the
    // deck's summary would evaluate it, so it is written only when the deck itself stopped.
    if (outcome.deck_stopped) {
      sim.deck_contact_end = lmp.number("t_contact_end").value_or(-1);
      lmp.file(decks.impact_dir + "/finish.in");
      sim.after = surface_profile(lmp, bed, crater_bin);
    }
  }
  r.steps = lmp.step() - first_step;
  r.sim_time_s = lmp.time_s();
  r.resumed_from_s = sim.resumed_from_s;
  if (rank == 0) remove_checkpoints(work);  // the run is over: nothing to resume
  return sim;
}

// The picture of the impact from the deck's frames; a picture that cannot be cut (no frame in
// contact) never fails the impact itself.
void attach_snapshot(ImpactResult& r, const ImpactSpec& spec, const ImpactContext& ctx) {
  if (ctx.picture_dir.empty()) return;
  try {
    r.snapshot = snapshot_from_frames(ctx.picture_dir, spec.id, r.dt_s);
  } catch (const std::exception& e) {
    std::cerr << "ricochet: warning: no impact picture for " << spec.id << ": " << e.what() << "\n";
  }
  std::error_code ec;
  fs::remove_all(ctx.picture_dir, ec);
}

}  // namespace

long acceptable_grain_loss(long atoms, long grains, long bed_grains, long block_spheres) {
  const long lost = bed_grains - grains;
  return atoms - grains == block_spheres && lost >= 0 && lost <= (bed_grains + 99) / 100 ? lost
                                                                                         : -1;
}

bool block_inserted(long atoms, long grains, long bed_grains, long block_spheres, bool resumed) {
  if (!resumed) return atoms == bed_grains + block_spheres;
  return acceptable_grain_loss(atoms, grains, bed_grains, block_spheres) >= 0;
}

ImpactResult run_impact(const ImpactSpec& spec, const ImpactContext& ctx, MPI_Comm comm) {
  const BedFiles& bed = ctx.bed;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  ImpactResult r = start_result(spec, ctx);
  const Shape shape = Shape::resolve(spec.shape);
  if (!bed.settled) {
    r.status = "bed_not_settled";
    r.message = "the bed " + bed.prefix + " did not meet its settling criterion";
    return r;
  }
  if (const std::string why = validate_setup(spec, shape, *ctx.decks, bed); !why.empty()) {
    r.status = "invalid";
    r.message = why;
    return r;
  }
  if (rank == 0) fs::create_directories(ctx.work_dir);
  MPI_Barrier(comm);
  const std::string out = (fs::path(ctx.work_dir) / "impact").string();
  const auto vars = deck_variables(spec, ctx, shape, out, rank, comm);

  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_s();
  const double crater_bin = 2 * bed.r_max_m;
  const Simulated sim = simulate(ctx, vars, crater_bin, r, comm);
  r.wall_s = seconds_since(start);
  // CPU time summed over the instance's ranks: the cost in core-seconds, which the other load of
  // a shared machine does not inflate the way it inflates the wall time.
  r.cpu_s = process_cpu_s() - cpu_start;
  MPI_Allreduce(MPI_IN_PLACE, &r.cpu_s, 1, MPI_DOUBLE, MPI_SUM, comm);
  r.wall_s += sim.earlier_wall_s;  // a resumed run counts its earlier segments
  r.cpu_s += sim.earlier_cpu_s;
  if (rank != 0) return r;
  attach_snapshot(r, spec, ctx);

  // ---- Extraction (rank 0 of the instance reads the deck's track file)
  if (!read_track(r, out, sim.overlaps)) return r;
  explain_status(r, sim.t_max);
  if (!r.ok()) return r;
  const auto window = force_window(r, spec, ctx, shape, sim);
  if (!window) return r;
  measure_crater(r, sim, shape, bed.r_max_m, crater_bin, window->first, window->second);
  extract_release(r, spec, ctx, shape);
  return r;
}

const std::vector<std::string>& impact_extra_names() {
  static const std::vector<std::string> names = {
      "energy_dissipated_frac", "crater_depth",  "crater_width",
      "vin_x_direct",           "vin_y_direct",  "win_direct",
      "vout_x_direct",          "vout_y_direct", "wout_direct",
      "force_contact_duration"};
  return names;
}

const std::vector<std::string>& impact_extra_units() {
  static const std::vector<std::string> units = {"-",     "m",   "m",   "m/s",   "m/s",
                                                 "rad/s", "m/s", "m/s", "rad/s", "s"};
  return units;
}

}  // namespace ricochet::dem
