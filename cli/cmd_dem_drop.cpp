// `ricochet dem drop`: spheres dropped vertically into a resolved bed from several heights, the
// bed's angle of repose, and the checks against Uehara et al. 2003 (PRL 90, 194301) and
// Katsuragi & Durian 2007 (Nature Physics 3, 420). See docs/commands/dem.md ("dem drop") and
// docs/granular-impact-checks.md.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bed.hpp"
#include "cli_common.hpp"
#include "common/error.hpp"
#include "drop.hpp"
#include "drop_store.hpp"
#include "granular_fits.hpp"
#include "mpi_session.hpp"
#include "params.hpp"

namespace ricochet::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct DropOptions {
  std::vector<double> heights = {0.05, 0.1, 0.2, 0.5, 1.0};
  std::vector<long> seeds;  // empty: the decks' own seeds (one bed, ids hH)
  std::vector<std::string> sets;
  std::string decks, cache = "dem-cache", work = "dem-work";
  double mu = 0;  // > 0: imposed, no repose run
  std::size_t half_window = 10;
  double stop_fraction = 0.1;
  double tolerance = 0.05;
  OutputOptions output;
};

json repose_json(const dem::ReposeResult& r) {
  return {{"status", r.status},
          {"message", r.message},
          {"angle_deg", r.slope.angle_deg},
          {"angle_se_deg", r.slope.angle_se_deg},
          {"slope", r.slope.slope},
          {"slope_se", r.slope.slope_se},
          {"mu", std::tan(r.slope.angle_deg * std::numbers::pi / 180)},
          {"fitted_bins", r.slope.n},
          {"fitted_x_m", {r.slope.x_lo_m, r.slope.x_hi_m}},
          {"grains", r.grains},
          {"wall_s", r.wall_s},
          {"work_dir", r.work_dir},
          {"profile_x_m", r.x_m},
          {"profile_h_m", r.h_m}};
}

json kd_json(const dem::KatsuragiDurianFit& f) {
  return {{"samples", f.n},
          {"g_mps2", f.g_mps2},
          {"g_se", f.g_se},
          {"d1_m", f.d1_m},
          {"d1_se", f.d1_se},
          {"m_over_d1_kg_per_m", f.drag_kg_per_m},
          {"m_over_d1_se", f.drag_se},
          {"k_Npm", f.k_Npm},
          {"k_se", f.k_se},
          {"residual_sd_mps2", f.residual_sd},
          {"variance_inflation", f.variance_inflation}};
}

void run_drop_command_on_rank(const DropOptions& o, const MpiSession& mpi) {
  const auto decks = dem::Decks::locate(o.decks);
  // --set: bed.* and block.* are checked like every dem command's; drop.* and repose.* against
  // the index variables of drop/setup.in and repose/in.repose (positive numbers).
  dem::DropSpec base;
  std::map<std::string, std::string> repose;
  const auto drop_params = dem::drop_deck_params(decks);
  const auto repose_params = dem::repose_deck_params(decks);
  for (const auto& s : o.sets) {
    const auto eq = s.find('=');
    const auto dot = s.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq)
      throw InputError("<command line>", 0, "--set",
                       "expected SECTION.NAME=VALUE, got '" + s + "'");
    const std::string section = s.substr(0, dot), name = s.substr(dot + 1, eq - dot - 1),
                      value = s.substr(eq + 1);
    if (section == "bed" || section == "block") {
      dem::Overrides ov;
      dem::apply_set_option(decks, s, ov);
      for (const auto& [k, v] : ov.bed) base.bed[k] = v;
      for (const auto& [k, v] : ov.block) base.block[k] = v;
      continue;
    }
    if (section != "drop" && section != "repose")
      throw InputError("<command line>", 0, "--set " + s,
                       "section must be bed, block, drop or repose");
    const auto& known = section == "drop" ? drop_params : repose_params;
    if (std::none_of(known.begin(), known.end(), [&](const auto& p) { return p.name == name; })) {
      std::string names;
      for (const auto& p : known)
        names += (names.empty() ? std::string() : std::string(", ")) + p.name;
      throw InputError("<command line>", 0, section + "." + name,
                       "unknown parameter (known: " + names + ")");
    }
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (end == value.c_str() || *end != '\0' || !(v >= 0) ||
        (v == 0 && name != "y_drop_m" && name != "h_start_m"))
      throw InputError("<command line>", 0, section + "." + name,
                       "'" + value + "' must be a positive number");
    (section == "drop" ? base.drop : repose)[name] = value;
  }
  std::string out = o.output.out;
  if (!out.empty()) require_extension("--out", out, {".csv"});
  for (double h : o.heights)
    if (!(h > 0)) throw InputError("<command line>", 0, "--heights", "heights must be > 0");

  // Drops already in the file are skipped (resume).
  const std::optional<dem::DropStore> store =
      out.empty() ? std::nullopt : std::optional<dem::DropStore>(dem::DropStore(out));
  const std::set<std::string> done = store ? store->done_ids() : std::set<std::string>{};

  // The angle of repose (once per output file, or imposed with --mu).
  json repose_doc;
  double mu = o.mu;
  if (mu <= 0) {
    const std::string rp = store ? store->repose_path() : "";
    if (!rp.empty() && fs::exists(rp)) {
      std::ifstream in(rp);
      repose_doc = json::parse(in);
    } else {
      const auto r = dem::run_repose(decks, dem::drop_bed_overrides(base), repose,
                                     (fs::path(o.work) / "repose").string(), MPI_COMM_WORLD);
      repose_doc = repose_json(r);
      if (mpi.rank() == 0 && !rp.empty()) write_text_file(rp, repose_doc.dump(1) + "\n", "--out");
      if (r.status == "failed")
        throw std::runtime_error("the repose run gave no slope: " + r.message +
                                 " (give --mu to impose the friction)");
    }
    mu = repose_doc.at("mu").get<double>();
  }

  // The drops.
  std::vector<std::pair<dem::DropResult, long>> fresh;
  dem::BedFiles bed;
  // No --seeds: one replica with the decks' own seeds (seed -1 in the file).
  const std::vector<long> seeds = o.seeds.empty() ? std::vector<long>{-1} : o.seeds;
  for (long seed : seeds)
    for (double h : o.heights) {
      dem::DropSpec spec = base;
      spec.h_drop_m = h;
      if (seed >= 0) {
        spec.id = fmt::format("h{}-s{}", shortest_number(h), seed);
        spec.seed = seed;
      } else {
        spec.id = fmt::format("h{}", shortest_number(h));
      }
      bed = dem::ensure_bed(decks, dem::drop_bed_overrides(spec), o.cache, MPI_COMM_WORLD);
      if (done.count(spec.id)) continue;
      dem::DropContext ctx;
      ctx.decks = &decks;
      ctx.bed = bed;
      ctx.work_dir = (fs::path(o.work) / spec.id).string();
      ctx.analysis = {o.half_window, o.stop_fraction};
      auto r = dem::run_drop(spec, ctx, MPI_COMM_WORLD);
      if (mpi.rank() == 0) {
        std::cerr << fmt::format("[dem drop] {}: {} ({}) in {:.0f} s\n", r.id, r.status, r.message,
                                 r.wall_s);
        if (store) store->append(r, seed);
      }
      fresh.emplace_back(std::move(r), seed);
    }
  if (mpi.rank() != 0) return;

  // Every drop of the study: the file's rows (with this run's), else this run's.
  struct Drop {
    dem::DropRow row;
    dem::DropTrack track;
  };
  std::vector<Drop> drops;
  if (store) {
    auto tracks = store->tracks();
    for (auto& row : store->rows()) drops.push_back({row, std::move(tracks[row.text("id")])});
  } else {
    for (auto& [r, seed] : fresh) drops.push_back({dem::drop_row(r, seed), r.track});
  }

  json list = json::array();
  std::vector<double> H, d, H_max, d_max;
  std::vector<dem::KdSample> pooled, pooled_force;
  std::size_t n_run = 0;
  double mass = NAN, rho_b = NAN, D_b = NAN, rho_g_sum = 0, wall_sum = 0, cpu_sum = 0;
  double grain_steps = 0;
  std::size_t n_ok = 0;
  const dem::DropAnalysisOptions analysis{o.half_window, o.stop_fraction};
  for (const auto& dr : drops) {
    json x;
    for (const auto& name : dem::drop_row_names()) {
      const std::string v = dr.row.text(name);
      char* end = nullptr;
      const double num_v = std::strtod(v.c_str(), &end);
      if (end != v.c_str() && *end == '\0')
        x[name] = std::isfinite(num_v) ? json(num_v) : json(nullptr);
      else
        x[name] = v;
    }
    // Uehara et al. 2003 Eq. (1) for this drop's own H and bulk density.
    if (std::isfinite(dr.row.number("H_total_m")) && dr.row.number("H_total_m") > 0)
      x["d_uehara_m"] =
          dem::uehara_depth_m(dr.row.number("H_total_m"), dr.row.number("rho_sphere"),
                              dr.row.number("rho_bulk"), dr.row.number("D_sphere_m"), mu);
    list.push_back(x);
    const std::string status = dr.row.text("status");
    if (status != "at_rest" && status != "rebound") continue;
    // A sphere that bounced off the bed has no resting depth (Uehara's d) but a penetration
    // phase on the way in (Katsuragi-Durian) and a largest depth.
    if (dr.row.number("depth_max_m") > 0) {
      H_max.push_back(dr.row.number("h_drop_m") + dr.row.number("depth_max_m"));
      d_max.push_back(dr.row.number("depth_max_m"));
    }
    ++n_run;
    mass = dr.row.number("mass_kg");
    rho_b = dr.row.number("rho_sphere");
    D_b = dr.row.number("D_sphere_m");
    rho_g_sum += dr.row.number("rho_bulk");
    wall_sum += dr.row.number("wall_s");
    cpu_sum += dr.row.number("cpu_s");
    grain_steps += dr.row.number("steps") * (dr.row.number("grains") + 1);
    if (status == "at_rest") {
      ++n_ok;
      H.push_back(dr.row.number("H_total_m"));
      d.push_back(dr.row.number("depth_final_m"));
    }
    const auto s = dem::drop_samples(dr.track, analysis, mass * dem::kDeckGravity_mps2);
    pooled.insert(pooled.end(), s.begin(), s.end());
    for (const auto& x : s)
      pooled_force.push_back({dr.track.depth[x.index], -dr.track.vz[x.index],
                              dem::kDeckGravity_mps2 - dr.track.fcz[x.index] / mass, x.index});
  }
  const double rho_g = n_run ? rho_g_sum / static_cast<double>(n_run) : NAN;
  json j = {{"out", out},
            {"ranks", mpi.size()},
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
            {"drop_overrides", base.drop},
            {"block_overrides", base.block},
            {"seeds", o.seeds},
            {"heights_m", o.heights},
            {"ran_now", fresh.size()},
            {"drops", list},
            {"mu", mu},
            {"mu_source", o.mu > 0 ? "--mu" : "repose run"}};
  if (!repose_doc.is_null()) {
    json rd = repose_doc;
    rd.erase("profile_x_m");
    rd.erase("profile_h_m");
    j["repose"] = rd;
  }
  if (n_run > 0) {
    // Grain size: the middle radius of the bed's three (the mass-weighted mean is within 5 %).
    const double d_g = 2 * std::stod(bed.values.count("r2_m") ? bed.values.at("r2_m") : "0");
    j["sphere"] = {{"D_m", D_b},
                   {"rho_kgm3", rho_b},
                   {"mass_kg", mass},
                   {"D_over_grain_diameter", d_g > 0 ? D_b / d_g : NAN}};
    j["rho_bulk_kgm3"] = rho_g;
    j["cost"] = {{"drops", n_run},
                 {"wall_s_per_drop", wall_sum / static_cast<double>(n_run)},
                 {"cpu_s_per_drop", cpu_sum / static_cast<double>(n_run)},
                 {"core_us_per_grain_step", grain_steps > 0 ? 1e6 * cpu_sum / grain_steps : NAN}};
  }
  std::string text;
  // Uehara's law on (H, d): the resting depths (the check), or the largest depths when fewer
  // than 3 drops stayed in the sand (a diagnostic only: the law is about resting depths).
  auto uehara = [&](const std::vector<double>& HH, const std::vector<double>& dd, const char* what,
                    bool is_check) {
    json u_json;
    try {
      const auto u = dem::check_uehara(HH, dd, rho_b, rho_g, D_b, mu, o.tolerance);
      u_json = {{"depth", what},
                {"drops", u.fit.n},
                {"exponent", u.fit.exponent},
                {"exponent_se", u.fit.exponent_se},
                {"exponent_minus_one_third", u.exponent_deviation},
                {"tolerance", u.tolerance},
                {"pass", is_check && u.exponent_pass},
                {"prefactor_A_m_power", u.fit.prefactor},
                {"residual_sd_log", u.fit.residual_sd_log},
                {"C_fitted", u.c_fitted},
                {"C_fitted_se", u.c_fitted_se},
                {"C_expected_0.14_over_mu", u.c_expected},
                {"C_ratio", u.c_fitted / u.c_expected},
                {"C_fitted_times_mu", u.c_fitted * mu}};
      text += fmt::format(
          "Uehara on the {} depths (d ~ H^n, {} drops): n = {:.3f} +- {:.3f} (1/3 {:+.3f}, "
          "tolerance {}): {}\n  prefactor C = {:.4f} +- {:.4f} against 0.14/mu = {:.3f} (ratio "
          "{:.3f}; C mu = {:.4f})\n",
          what, u.fit.n, u.fit.exponent, u.fit.exponent_se, u.exponent_deviation, u.tolerance,
          is_check ? (u.exponent_pass ? "PASS" : "FAIL") : "diagnostic only", u.c_fitted,
          u.c_fitted_se, u.c_expected, u.c_fitted / u.c_expected, u.c_fitted * mu);
    } catch (const std::invalid_argument& e) {
      u_json = {{"depth", what}, {"error", e.what()}, {"pass", false}};
    }
    return u_json;
  };
  if (n_ok >= 3) {
    j["uehara"] = uehara(H, d, "resting", true);
  } else {
    j["uehara"] = {{"pass", false},
                   {"error", fmt::format("{} of {} drops came to rest in the sand (the others "
                                         "bounced off or failed): Uehara's law needs resting "
                                         "depths of at least 3",
                                         n_ok, drops.size())}};
    text += "Uehara: FAIL, " + j["uehara"]["error"].get<std::string>() + "\n";
    if (d_max.size() >= 3) j["uehara_largest_depth"] = uehara(H_max, d_max, "largest", false);
  }
  if (pooled.size() > 10) {
    const double inflation = static_cast<double>(2 * o.half_window + 1);
    json kd;
    try {
      const auto f = dem::fit_katsuragi_durian(pooled, mass, inflation);
      const auto ff = dem::fit_katsuragi_durian(pooled_force, mass, inflation);
      const auto fg = dem::fit_katsuragi_durian(pooled, mass, inflation, dem::kDeckGravity_mps2);
      kd["trajectory"] = kd_json(f);
      kd["force"] = kd_json(ff);
      kd["trajectory_g_fixed"] = kd_json(fg);
      // Against the catalog's inertial_drag (cd = m / d1 [kg/m], bounds [0, 5000]; the detection
      // benchmark's truth uses m/d1 = 40 kg/m = rho_g x 0.08 m x 0.29 m for the lab cylinder):
      // the sphere's m / d1 in units of rho_g x its projected area, carried to the lab block.
      const double area = std::numbers::pi / 4 * D_b * D_b;
      const double c_drag = f.drag_kg_per_m / (rho_g * area);
      const double c_k = f.k_Npm / (rho_g * dem::kDeckGravity_mps2 * area);
      kd["inertial_drag"] = {
          {"cd_bounds_kg_per_m", {0.0, 5000.0}},
          {"cd_detection_benchmark_kg_per_m", 40.0},
          {"sphere_m_over_d1_kg_per_m", f.drag_kg_per_m},
          {"m_over_d1_over_rho_g_area", c_drag},
          {"lab_cylinder_cd_kg_per_m", c_drag * rho_g * 0.08 * 0.29},
          {"k_over_rho_g_g_area", c_k},
          {"lab_cylinder_k_Npm", c_k * rho_g * dem::kDeckGravity_mps2 * 0.08 * 0.29}};
      text += fmt::format(
          "Katsuragi-Durian (pooled, {} samples): g = {:.2f} +- {:.2f} m/s^2, d1 = {:.4f} +- "
          "{:.4f} m (m/d1 = {:.2f} +- {:.2f} kg/m), k = {:.0f} +- {:.0f} N/m\n"
          "  from the DEM force: g = {:.2f}, d1 = {:.4f} m, k = {:.0f} N/m\n"
          "  m/d1 = {:.2f} rho_g A; carried to the lab cylinder: cd = {:.0f} kg/m (catalog "
          "inertial_drag cd in [0, 5000], benchmark truth 40)\n",
          f.n, f.g_mps2, f.g_se, f.d1_m, f.d1_se, f.drag_kg_per_m, f.drag_se, f.k_Npm, f.k_se,
          ff.g_mps2, ff.d1_m, ff.k_Npm, c_drag, c_drag * rho_g * 0.08 * 0.29);
    } catch (const std::invalid_argument& e) {
      kd["error"] = e.what();
    }
    j["katsuragi_durian"] = kd;
  }
  if (o.output.json) {
    print_json(j);
    return;
  }
  std::cout << fmt::format("dem drop: {} drops ({} at rest, {} run now), mu = {:.3f} ({})\n",
                           drops.size(), n_ok, fresh.size(), mu,
                           o.mu > 0 ? "imposed" : "repose run");
  auto getd = [](const json& x, const char* k) {
    return x.contains(k) && x[k].is_number() ? x[k].get<double>() : NAN;
  };
  for (const auto& x : list)
    std::cout << fmt::format(
        "  {:>12} {:>10}  h = {:.3f} m  d = {:.4f} m (Uehara {:.4f} m)  H = {:.4f} m\n",
        x.value("id", ""), x.value("status", ""), getd(x, "h_drop_m"), getd(x, "depth_final_m"),
        getd(x, "d_uehara_m"), getd(x, "H_total_m"));
  std::cout << text;
}

void run_drop_command(const DropOptions& o) {
  MpiSession mpi;
  mpi.run([&] { run_drop_command_on_rank(o, mpi); });
}

}  // namespace

void add_dem_drop_command(CLI::App& dem) {
  auto o = std::make_shared<DropOptions>();
  auto* s = dem.add_subcommand(
      "drop", "Drop a sphere into a bed from several heights; Uehara and Katsuragi-Durian checks");
  s->add_option("--heights", o->heights, "Drop heights [m] (sphere bottom above the surface)")
      ->delimiter(',');
  s->add_option("--seeds", o->seeds,
                "Replica seeds (a bed per seed; default: the decks' own seeds, one bed)")
      ->delimiter(',');
  s->add_option("--set", o->sets,
                "SECTION.NAME=VALUE, SECTION bed, block, drop (drop/setup.in) or repose "
                "(repose/in.repose); repeatable");
  s->add_option("--decks", o->decks, "liggghts-inputs folder");
  s->add_option("--cache", o->cache, "Bed cache folder");
  s->add_option("--work", o->work, "Work folder (per-drop logs and tracks)");
  s->add_option("--mu", o->mu, "Impose mu = tan(repose angle) instead of running the repose deck");
  s->add_option("--half-window", o->half_window, "Derivative half-window [records]");
  s->add_option("--stop-fraction", o->stop_fraction,
                "End of the fitted penetration phase: speed below this x impact speed");
  s->add_option("--tolerance", o->tolerance, "Largest |exponent - 1/3| that passes");
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
