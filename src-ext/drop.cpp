#include "drop.hpp"

#include <sys/resource.h>

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "chunk_run.hpp"
#include "common/clock.hpp"
#include "common/nan.hpp"
#include "impact_run.hpp"
#include "liggghts.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kColumns = 11;

double process_cpu_s() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Value of a drop.* parameter: the override, else the deck's default.
double drop_param(const DropSpec& spec, const Decks& decks, const std::string& name) {
  if (const auto it = spec.drop.find(name); it != spec.drop.end()) return std::stod(it->second);
  for (const auto& p : drop_deck_params(decks))
    if (p.name == name) return std::stod(p.default_value);
  throw std::logic_error("drop deck has no parameter " + name);
}

}  // namespace

std::vector<DeckParam> drop_deck_params(const Decks& decks) {
  auto all = read_deck_params(decks.root + "/drop/setup.in");
  // Wiring set by the driver, not parameters.
  std::erase_if(all, [](const DeckParam& p) {
    return p.name == "deck_dir" || p.name == "common" || p.name == "bed" || p.name == "out" ||
           p.name == "h_drop_m";
  });
  return all;
}

std::vector<DeckParam> repose_deck_params(const Decks& decks) {
  auto all = read_deck_params(decks.root + "/repose/in.repose");
  // in.repose includes grain-defaults.in: only its own section is read here (the file's own
  // index lines), minus the wiring.
  std::erase_if(all, [](const DeckParam& p) { return p.name == "common" || p.name == "out"; });
  return all;
}

std::map<std::string, std::string> drop_bed_overrides(const DropSpec& spec) {
  return with_replica_seed(spec.bed, spec.seed);
}

const std::vector<std::string>& DropTrack::column_names() {
  static const std::vector<std::string> names = {"t[s]",    "x[m]",    "y[m]",        "depth[m]",
                                                 "vx[m/s]", "vy[m/s]", "vz[m/s]",     "fcx[N]",
                                                 "fcy[N]",  "fcz[N]",  "ke_grains[J]"};
  return names;
}

const std::vector<double>& DropTrack::column(std::size_t c) const {
  const std::vector<double>* cols[kColumns] = {&t,  &x,   &y,   &depth, &vx,       &vy,
                                               &vz, &fcx, &fcy, &fcz,   &ke_grains};
  if (c >= kColumns) throw std::out_of_range("DropTrack column");
  return *cols[c];
}

std::vector<double>& DropTrack::column(std::size_t c) {
  return const_cast<std::vector<double>&>(std::as_const(*this).column(c));
}

DropTrack DropTrack::read(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read the sphere track " + path);
  DropTrack tr;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    double v[kColumns];
    bool complete = true;
    for (double& x : v) {
      std::string cell;
      if (!(ls >> cell)) {
        complete = false;
        break;
      }
      x = std::strtod(cell.c_str(), nullptr);
    }
    if (!complete) continue;  // a line cut by a crash
    if (!tr.t.empty() && v[0] <= tr.t.back()) continue;
    for (std::size_t c = 0; c < kColumns; ++c) tr.column(c).push_back(v[c]);
  }
  return tr;
}

std::vector<KdSample> drop_samples(const DropTrack& track, const DropAnalysisOptions& options,
                                   double weight_N) {
  if (track.size() < 2 * options.half_window + 1) return {};
  double z_start = 0;
  for (std::size_t i = 0; i < track.size(); ++i)
    if (track.fcz[i] > 0.05 * weight_N) {
      z_start = std::min(0.0, track.depth[i]);
      break;
    }
  return penetration_samples(track.t, track.depth, options.half_window, options.stop_fraction,
                             z_start);
}

std::size_t remove_torn_records(DropTrack& track, double mass_kg) {
  if (track.size() < 2 || !(mass_kg > 0)) return 0;
  double f_max = 0;
  for (std::size_t i = 0; i < track.size(); ++i)
    f_max = std::max(f_max, std::hypot(track.fcx[i], track.fcy[i], track.fcz[i]));
  const double a_bound = 3 * (kDeckGravity_mps2 + f_max / mass_kg);
  std::vector<std::size_t> keep = {0};
  for (std::size_t i = 1; i < track.size(); ++i) {
    const std::size_t j = keep.back();
    const double dv =
        std::hypot(track.vx[i] - track.vx[j], track.vy[i] - track.vy[j], track.vz[i] - track.vz[j]);
    if (dv <= a_bound * (track.t[i] - track.t[j])) keep.push_back(i);
  }
  const std::size_t removed = track.size() - keep.size();
  // A first record torn would make every other one look torn: keep the track as it is then.
  if (removed == 0 || removed > track.size() / 100) return 0;
  for (std::size_t c = 0; c < DropTrack::column_names().size(); ++c) {
    std::vector<double>& col = track.column(c);
    std::vector<double> kept;
    kept.reserve(keep.size());
    for (std::size_t i : keep) kept.push_back(col[i]);
    col = std::move(kept);
  }
  return removed;
}

void analyse_drop(DropResult& r, const DropAnalysisOptions& options) {
  r.torn_records = remove_torn_records(r.track, r.mass_kg);
  const DropTrack& tr = r.track;
  if (tr.size() == 0) return;
  r.depth_max_m = *std::max_element(tr.depth.begin(), tr.depth.end());
  // At rest: the mean depth over the last t_rest_s-worth of records (the last tenth, at least 1).
  const std::size_t tail = std::max<std::size_t>(1, tr.size() / 10);
  double sum = 0;
  for (std::size_t i = tr.size() - tail; i < tr.size(); ++i) sum += tr.depth[i];
  r.depth_final_m = sum / static_cast<double>(tail);
  // Uehara et al. 2003: H = h + d, the total distance fallen by the sphere.
  r.H_total_m = r.h_drop_m + r.depth_final_m;
  r.v_impact_mps = kNaN;
  for (std::size_t i = 1; i < tr.size(); ++i)
    if (tr.depth[i - 1] < 0 && tr.depth[i] >= 0) {
      const double f = -tr.depth[i - 1] / (tr.depth[i] - tr.depth[i - 1]);
      r.v_impact_mps = -(tr.vz[i - 1] + f * (tr.vz[i] - tr.vz[i - 1]));
      break;
    }
  r.v_rebound_mps = 0;
  for (std::size_t i = 0; i < tr.size(); ++i)
    if (tr.fcz[i] > 0.05 * r.mass_kg * kDeckGravity_mps2) {
      r.v_contact_mps = -tr.vz[i];
      r.depth_contact_m = tr.depth[i];
      break;
    }
  for (std::size_t i = 0; i < tr.size(); ++i)
    if (r.t_contact_s >= 0 && tr.t[i] >= r.t_contact_s)
      r.v_rebound_mps = std::max(r.v_rebound_mps, tr.vz[i]);
  const auto samples = drop_samples(tr, options, r.mass_kg * kDeckGravity_mps2);
  r.kd_samples = samples.size();
  // The derivative window correlates 2 w + 1 neighbouring samples: inflate the variances so.
  const double inflation = static_cast<double>(2 * options.half_window + 1);
  if (samples.size() >= 2 * options.half_window + 4) {
    try {
      r.kd_trajectory = fit_katsuragi_durian(samples, r.mass_kg, inflation);
    } catch (const std::invalid_argument&) {
      r.kd_trajectory.reset();
    }
    // The same phase with the DEM's contact force as the acceleration: z'' = g - F_z / m
    // (z positive down, F_z the upward contact force).
    std::vector<KdSample> force;
    for (const auto& s : samples)
      force.push_back({tr.depth[s.index], -tr.vz[s.index],
                       kDeckGravity_mps2 - tr.fcz[s.index] / r.mass_kg, s.index});
    try {
      // Instantaneous forces: correlated over a grain contact time, a few records.
      r.kd_force = fit_katsuragi_durian(force, r.mass_kg, inflation);
    } catch (const std::invalid_argument&) {
      r.kd_force.reset();
    }
    r.t_penetration_s = tr.t[samples.back().index] - tr.t[samples.front().index];
  }
}

namespace {

// What would make LIGGGHTS stop or the drop meaningless, checked before LIGGGHTS runs: the
// message, empty when the drop can run.
std::string preflight_problem(const DropSpec& spec, const Decks& decks, const BedFiles& bed,
                              const DropResult& r) {
  const double h_start = drop_param(spec, decks, "h_start_m");
  const double x_frac = drop_param(spec, decks, "x_drop_frac");
  const double y_drop = drop_param(spec, decks, "y_drop_m");
  const double R = 0.5 * r.D_sphere_m;
  const double x = x_frac * bed.Lx_m;
  const double z_top = bed.z_surface_m + std::min(h_start, spec.h_drop_m) + 2 * R;
  if (!(spec.h_drop_m > 0)) return fmt::format("drop height {} m: must be > 0", spec.h_drop_m);
  if (x - R < 2 * bed.r_max_m || x + R > bed.Lx_m - 2 * bed.r_max_m ||
      std::abs(y_drop) + R > 0.5 * bed.Ly_m - 2 * bed.r_max_m)
    return fmt::format(
        "a sphere of diameter {} m at x = {} m, y = {} m does not fit the {} x {} m bed",
        r.D_sphere_m, x, y_drop, bed.Lx_m, bed.Ly_m);
  if (z_top > bed.z_box_top_m)
    return fmt::format("the sphere's top would be at {:.3f} m, above the box top {:.3f} m", z_top,
                       bed.z_box_top_m);
  return "";
}

// The deck's variables of one drop.
std::vector<std::pair<std::string, std::string>> drop_variables(const DropSpec& spec,
                                                                const Decks& decks,
                                                                const BedFiles& bed,
                                                                const std::string& out) {
  std::vector<std::pair<std::string, std::string>> vars = {
      {"deck_dir", decks.root + "/drop"},
      {"common", decks.common},
      {"bed", bed.prefix},
      {"out", out},
      {"h_drop_m", shortest_number(spec.h_drop_m)}};
  for (const auto& [k, v] : spec.block) vars.emplace_back(k, v);
  for (const auto& [k, v] : spec.drop) vars.emplace_back(k, v);
  if (spec.seed && !spec.drop.count("sphere_seed"))
    vars.emplace_back("sphere_seed", std::to_string(liggghts_seed(*spec.seed, 1)));
  return vars;
}

// The LIGGGHTS run: the sphere inserted, then chunks until the deck's stop criterion; fills the
// status, time step, bulk density, steps and simulated time of `r`.
void run_liggghts_drop(const DropContext& ctx, const BedFiles& bed,
                       const std::vector<std::pair<std::string, std::string>>& vars,
                       const std::string& deck_dir, MPI_Comm comm, DropResult& r) {
  Liggghts lmp(comm, (fs::path(ctx.work_dir) / "log.liggghts").string(),
               (fs::path(ctx.work_dir) / "screen.txt").string(), vars);
  lmp.file(deck_dir + "/setup.in");
  r.dt_s = lmp.timestep_s();
  const long first_step = lmp.step();
  r.rho_bulk = lmp.number("rho_bulk").value_or(kNaN);
  const double t_max = lmp.number("t_max_s").value_or(0);
  const long chunk = static_cast<long>(lmp.number("chunk_steps").value_or(100));
  const long expected = bed.grains + 1;
  if (lmp.natoms() != expected) {
    r.status = "not_inserted";
    r.message = fmt::format("{} atoms after the sphere's insertion, expected {} grains + 1",
                            lmp.natoms(), bed.grains);
  } else {
    ChunkRun run;
    run.chunk_steps = chunk;
    run.check_file = deck_dir + "/check.in";
    run.done_variable = "drop_done";
    run.body = "sphere";
    run.state_variables = {"sx", "sy", "sz", "svz"};
    run.expected_atoms = expected;
    if (ctx.progress) run.progress = [&](double t) { ctx.progress(t, t_max); };
    const ChunkOutcome outcome = run_chunks(lmp, run);
    r.status = outcome.status;
    r.message = outcome.message;
    if (outcome.deck_stopped) {
      r.t_contact_s = lmp.number("t_contact_start").value_or(-1);
      lmp.file(deck_dir + "/finish.in");
    }
  }
  r.steps = lmp.step() - first_step;
  r.sim_time_s = lmp.time_s();
}

// The one-line summary of an analysed drop, by status.
void outcome_message(DropResult& r) {
  if (r.status == "at_rest")
    r.message = fmt::format("d = {:.4f} m after h = {:.3f} m (H = {:.4f} m), impact at {:.3f} m/s",
                            r.depth_final_m, r.h_drop_m, r.H_total_m, r.v_impact_mps);
  else if (r.status == "timeout")
    r.message = fmt::format("still moving after t_max_s (depth {:.4f} m)", r.depth_final_m);
  else if (r.status == "rebound")
    r.message = fmt::format(
        "bounced off the bed at {:.3f} m/s after an impact at {:.3f} m/s, largest depth {:.4f} m",
        r.v_rebound_mps, r.v_impact_mps, r.depth_max_m);
  else if (r.status == "bottom")
    r.message = "the sphere reached the floor: use a deeper bed (bed.H_m)";
  if (r.torn_records > 0)
    r.message += fmt::format(" ({} torn track record{} removed)", r.torn_records,
                             r.torn_records == 1 ? "" : "s");
}

}  // namespace

DropResult run_drop(const DropSpec& spec, const DropContext& ctx, MPI_Comm comm) {
  const Decks& decks = *ctx.decks;
  const BedFiles& bed = ctx.bed;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  DropResult r;
  r.id = spec.id;
  r.h_drop_m = spec.h_drop_m;
  r.bed_key = bed.key;
  r.grains = bed.grains;
  r.dt_s = bed.dt_s;
  r.work_dir = ctx.work_dir;
  r.D_sphere_m = drop_param(spec, decks, "D_sphere_m");
  r.rho_sphere = drop_param(spec, decks, "rho_sphere");
  r.mass_kg = std::numbers::pi / 6 * std::pow(r.D_sphere_m, 3) * r.rho_sphere;
  if (!bed.settled) {
    r.status = "bed_not_settled";
    r.message = "the bed " + bed.prefix + " did not meet its settling criterion";
    return r;
  }
  r.message = preflight_problem(spec, decks, bed, r);
  if (!r.message.empty()) {
    r.status = "invalid";
    return r;
  }
  if (rank == 0) fs::create_directories(ctx.work_dir);
  MPI_Barrier(comm);
  const std::string out = (fs::path(ctx.work_dir) / "drop").string();
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_s();
  run_liggghts_drop(ctx, bed, drop_variables(spec, decks, bed, out), decks.root + "/drop", comm, r);
  r.wall_s = seconds_since(start);
  r.cpu_s = process_cpu_s() - cpu_start;
  MPI_Allreduce(MPI_IN_PLACE, &r.cpu_s, 1, MPI_DOUBLE, MPI_SUM, comm);
  if (rank != 0) return r;
  try {
    r.track = DropTrack::read(out + ".track.txt");
  } catch (const std::exception& e) {
    if (r.ok()) {
      r.status = "nan";
      r.message = e.what();
    }
    return r;
  }
  analyse_drop(r, ctx.analysis);
  outcome_message(r);
  return r;
}

ReposeResult run_repose(const Decks& decks, const std::map<std::string, std::string>& bed,
                        const std::map<std::string, std::string>& repose,
                        const std::string& work_dir, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  ReposeResult r;
  r.work_dir = work_dir;
  if (rank == 0) fs::create_directories(work_dir);
  MPI_Barrier(comm);
  std::vector<std::pair<std::string, std::string>> vars = {
      {"common", decks.common}, {"out", (fs::path(work_dir) / "repose").string()}};
  // Only the grains' parameters: the deck builds its own geometry.
  for (const auto& [k, v] : bed)
    if (k != "mode" && k != "Lx_m" && k != "Ly_m" && k != "H_m" && k != "headroom_m")
      vars.emplace_back(k, v);
  for (const auto& [k, v] : repose) vars.emplace_back(k, v);
  double L_floor = 0.4;
  for (const auto& p : repose_deck_params(decks))
    if (p.name == "L_floor_m") L_floor = std::stod(p.default_value);
  if (const auto it = repose.find("L_floor_m"); it != repose.end()) L_floor = std::stod(it->second);
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> profile;
  double r_max = 0;
  {
    Liggghts lmp(comm, (fs::path(work_dir) / "log.liggghts").string(),
                 (fs::path(work_dir) / "screen.txt").string(), vars);
    lmp.file(decks.root + "/repose/in.repose");
    r.grains = lmp.natoms();
    r_max = lmp.number("r_max_m").value_or(0.005);
    const bool settled = lmp.number("repose_settled").value_or(0) == 1.0;
    r.status = settled ? "ok" : "not_settled";
    // The surface profile: the impact driver's crater profile (mean top of the top layer in bins
    // of 2 r_max along x) on the heap.
    BedFiles geometry;
    geometry.Lx_m = L_floor;
    geometry.r_max_m = r_max;
    profile = surface_profile(lmp, geometry, 2 * r_max);
  }
  r.wall_s = seconds_since(start);
  for (std::size_t b = 0; b < profile.size(); ++b) {
    r.x_m.push_back((static_cast<double>(b) + 0.5) * 2 * r_max);
    r.h_m.push_back(profile[b]);
  }
  try {
    r.slope = fit_repose_slope(r.x_m, r.h_m);
    r.message = fmt::format("angle of repose {:.1f} +- {:.1f} deg ({} profile bins)",
                            r.slope.angle_deg, r.slope.angle_se_deg, r.slope.n);
  } catch (const std::invalid_argument& e) {
    r.status = "failed";
    r.message = e.what();
  }
  return r;
}

}  // namespace ricochet::dem
