#include "drop_analysis.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/json_number.hpp"
#include "effects/registry.hpp"
#include "engine/shape.hpp"

namespace ricochet::dem {

namespace {

using nlohmann::json;

bool reached_bed(const DropRow& row) {
  const std::string status = row.text("status");
  return status == "at_rest" || status == "rebound";
}

// The depths a study fits Uehara's law on: resting depths (drops at rest) and largest depths
// (every drop that reached the bed and went below the surface: a sphere that bounced off has no
// resting depth but a largest one).
struct Depths {
  std::vector<double> H, d, H_max, d_max;
};

UeharaOutcome uehara_outcome(const Depths& depths, bool resting, const DropStudyAnalysis& a,
                             double tolerance) {
  UeharaOutcome u;
  u.depth = resting ? "resting" : "largest";
  u.is_check = resting;
  try {
    u.check = check_uehara(resting ? depths.H : depths.H_max, resting ? depths.d : depths.d_max,
                           a.rho_sphere_kgm3, a.rho_bulk_kgm3, a.D_sphere_m, a.mu, tolerance);
  } catch (const std::invalid_argument& e) {
    u.error = e.what();
  }
  return u;
}

KatsuragiDurianOutcome katsuragi_durian_outcome(std::span<const KdSample> pooled,
                                                std::span<const KdSample> pooled_force,
                                                const DropStudyAnalysis& a,
                                                std::size_t half_window) {
  // Neighbouring derivatives share their window: 2 half_window + 1 records (least_squares).
  const double inflation = static_cast<double>(2 * half_window + 1);
  KatsuragiDurianOutcome kd;
  try {
    kd.trajectory = fit_katsuragi_durian(pooled, a.mass_kg, inflation);
    kd.force = fit_katsuragi_durian(pooled_force, a.mass_kg, inflation);
    kd.g_fixed = fit_katsuragi_durian(pooled, a.mass_kg, inflation, kDeckGravity_mps2);
  } catch (const std::invalid_argument& e) {
    // One failed fit and none is reported.
    KatsuragiDurianOutcome failed;
    failed.error = e.what();
    return failed;
  }
  kd.inertial_drag = compare_inertial_drag(*kd.trajectory, a.D_sphere_m, a.rho_bulk_kgm3);
  return kd;
}

// A JSON number when `text` is one (NaN and infinities as null), else the text.
json cell_json(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() && *end == '\0') return finite_or_null(v);
  return text;
}

// One drop of the JSON document: the row's cells and Uehara's depth for its H.
json drop_json(const StudyDrop& drop, const std::optional<double>& d_uehara_m) {
  json x;
  for (const auto& name : drop_row_names()) x[name] = cell_json(drop.row.text(name));
  if (d_uehara_m) x["d_uehara_m"] = *d_uehara_m;
  return x;
}

json uehara_json(const UeharaOutcome& u, double mu) {
  if (!u.check) return {{"depth", u.depth}, {"error", u.error}, {"pass", false}};
  const UeharaCheck& c = *u.check;
  return {{"depth", u.depth},
          {"drops", c.fit.n},
          {"exponent", c.fit.exponent},
          {"exponent_se", c.fit.exponent_se},
          {"exponent_minus_one_third", c.exponent_deviation},
          {"tolerance", c.tolerance},
          {"pass", u.is_check && c.exponent_pass},
          {"prefactor_A_m_power", c.fit.prefactor},
          {"residual_sd_log", c.fit.residual_sd_log},
          {"C_fitted", c.c_fitted},
          {"C_fitted_se", c.c_fitted_se},
          {"C_expected_0.14_over_mu", c.c_expected},
          {"C_ratio", c.c_fitted / c.c_expected},
          {"C_fitted_times_mu", c.c_fitted * mu}};
}

std::string uehara_text(const UeharaOutcome& u, double mu) {
  if (!u.check) return "";
  const UeharaCheck& c = *u.check;
  return fmt::format(
      "Uehara on the {} depths (d ~ H^n, {} drops): n = {:.3f} +- {:.3f} (1/3 {:+.3f}, "
      "tolerance {}): {}\n  prefactor C = {:.4f} +- {:.4f} against 0.14/mu = {:.3f} (ratio "
      "{:.3f}; C mu = {:.4f})\n",
      u.depth, c.fit.n, c.fit.exponent, c.fit.exponent_se, c.exponent_deviation, c.tolerance,
      u.is_check ? (c.exponent_pass ? "PASS" : "FAIL") : "diagnostic only", c.c_fitted,
      c.c_fitted_se, c.c_expected, c.c_fitted / c.c_expected, c.c_fitted * mu);
}

// d = A v^n over the resting drops with an impact speed, and Uehara's exponent at the same
// drops (SpeedScaling). Empty with fewer than 3 such drops or without Uehara's resting fit.
std::optional<SpeedScaling> speed_scaling(const DropStudyAnalysis& a) {
  if (!a.uehara || !a.uehara->check) return std::nullopt;
  // Uehara's law as fitted on these drops, exponent fixed: d = C' H^(1/3).
  const double c_prime = a.uehara->check->c_fitted * a.uehara->check->scale;
  std::vector<double> v, d, d_uehara;
  SpeedScaling s;
  s.d_over_v_min_s = s.t_penetration_min_s = INFINITY;
  s.d_over_v_max_s = s.t_penetration_max_s = -INFINITY;
  for (const auto& [row, track] : a.drops) {
    const double speed = row.number("v_impact_mps"), depth = row.number("depth_final_m");
    const double h = row.number("h_drop_m"), t_pen = row.number("t_penetration_s");
    if (row.text("status") != "at_rest" || !(speed > 0) || !(depth > 0) || !(h > 0)) continue;
    v.push_back(speed);
    d.push_back(depth);
    double du = depth;  // the fixed point of d = C' (h + d)^(1/3), a contraction for d << h
    for (int i = 0; i < 200; ++i) du = c_prime * std::cbrt(h + du);
    d_uehara.push_back(du);
    s.d_over_v_min_s = std::min(s.d_over_v_min_s, depth / speed);
    s.d_over_v_max_s = std::max(s.d_over_v_max_s, depth / speed);
    if (t_pen > 0) {
      s.t_penetration_min_s = std::min(s.t_penetration_min_s, t_pen);
      s.t_penetration_max_s = std::max(s.t_penetration_max_s, t_pen);
    }
  }
  if (v.size() < 3) return std::nullopt;
  try {
    s.fit = fit_power_law(v, d);
    s.uehara_exponent = fit_power_law(v, d_uehara).exponent;
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
  if (!std::isfinite(s.t_penetration_min_s)) s.t_penetration_min_s = s.t_penetration_max_s = NAN;
  return s;
}

json speed_scaling_json(const SpeedScaling& s) {
  return {{"drops", s.fit.n},
          {"exponent", s.fit.exponent},
          {"exponent_se", s.fit.exponent_se},
          {"prefactor", s.fit.prefactor},
          {"uehara_exponent", s.uehara_exponent},
          {"deceleration_proportional_to_speed_exponent", 1.0},
          {"d_over_v_s", {finite_or_null(s.d_over_v_min_s), finite_or_null(s.d_over_v_max_s)}},
          {"t_penetration_s",
           {finite_or_null(s.t_penetration_min_s), finite_or_null(s.t_penetration_max_s)}}};
}

std::string speed_scaling_text(const SpeedScaling& s) {
  return fmt::format(
      "Depth against impact speed (d ~ v^n, {} drops at rest): n = {:.3f} +- {:.3f}; Uehara's law "
      "at these drops {:.3f}, a deceleration proportional to the impact speed (Pica Ciamarra et "
      "al. 2004) 1\n  d / v {:.1f}-{:.1f} ms; penetration phase {:.3f}-{:.3f} s\n",
      s.fit.n, s.fit.exponent, s.fit.exponent_se, s.uehara_exponent, 1e3 * s.d_over_v_min_s,
      1e3 * s.d_over_v_max_s, s.t_penetration_min_s, s.t_penetration_max_s);
}

json viscous_fit_json(const ViscousDragFit& f) {
  return {{"samples", f.n},
          {"g_mps2", f.g_mps2},
          {"g_se", f.g_se},
          {"b_Nspm", f.b_Nspm},
          {"b_se", f.b_se},
          {"m_over_d1_kg_per_m", f.drag_kg_per_m},
          {"m_over_d1_se", f.drag_se},
          {"k_Npm", f.k_Npm},
          {"k_se", f.k_se},
          {"time_constant_s", f.mass_kg / f.b_Nspm},
          {"residual_sd_mps2", f.residual_sd}};
}

json viscous_json(const ViscousExtension& v) {
  json per = json::array();
  for (const auto& [id, f] : v.per_drop) {
    json x = f ? viscous_fit_json(*f) : json{{"error", "no fit"}};
    x["id"] = id;
    per.push_back(x);
  }
  json j = {{"exploratory", true}, {"per_drop", per}};
  if (v.pooled) j["pooled"] = viscous_fit_json(*v.pooled);
  return j;
}

std::string viscous_text(const ViscousExtension& v) {
  std::string t = "Katsuragi-Durian + viscous b z' (exploratory), g per drop:";
  for (const auto& [id, f] : v.per_drop)
    t += f ? fmt::format(" {} {:.1f} +- {:.1f}", id, f->g_mps2, f->g_se) : " " + id + " -";
  t += " m/s^2\n";
  if (v.pooled)
    t += fmt::format(
        "  pooled: g = {:.2f} +- {:.2f} m/s^2, b = {:.1f} +- {:.1f} N s/m (m/b = {:.4f} s), m/d1 = "
        "{:.1f} +- {:.1f} kg/m, k = {:.0f} +- {:.0f} N/m\n",
        v.pooled->g_mps2, v.pooled->g_se, v.pooled->b_Nspm, v.pooled->b_se,
        v.pooled->mass_kg / v.pooled->b_Nspm, v.pooled->drag_kg_per_m, v.pooled->drag_se,
        v.pooled->k_Npm, v.pooled->k_se);
  return t;
}

// Why the Uehara check failed when fewer than 3 drops came to rest.
std::string too_few_at_rest(const DropStudyAnalysis& a) {
  return fmt::format(
      "{} of {} drops came to rest in the sand (the others bounced off or failed): Uehara's law "
      "needs resting depths of at least 3",
      a.n_at_rest, a.drops.size());
}

json kd_fit_json(const KatsuragiDurianFit& f) {
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

json katsuragi_durian_json(const KatsuragiDurianOutcome& kd) {
  json j;
  if (!kd.trajectory) {
    j["error"] = kd.error;
    return j;
  }
  const InertialDragComparison& c = *kd.inertial_drag;
  j["trajectory"] = kd_fit_json(*kd.trajectory);
  j["force"] = kd_fit_json(*kd.force);
  j["trajectory_g_fixed"] = kd_fit_json(*kd.g_fixed);
  j["inertial_drag"] = {{"cd_bounds_kg_per_m", {c.cd_lower_kg_per_m, c.cd_upper_kg_per_m}},
                        {"cd_detection_benchmark_kg_per_m", kDetectionBenchmarkDrag_kg_per_m},
                        {"sphere_m_over_d1_kg_per_m", kd.trajectory->drag_kg_per_m},
                        {"m_over_d1_over_rho_g_area", c.m_over_d1_over_rho_g_area},
                        {"lab_cylinder_cd_kg_per_m", c.lab_cylinder_cd_kg_per_m},
                        {"k_over_rho_g_g_area", c.k_over_rho_g_g_area},
                        {"lab_cylinder_k_Npm", c.lab_cylinder_k_Npm}};
  return j;
}

std::string katsuragi_durian_text(const KatsuragiDurianOutcome& kd) {
  if (!kd.trajectory) return "";
  const KatsuragiDurianFit &f = *kd.trajectory, &ff = *kd.force;
  const InertialDragComparison& c = *kd.inertial_drag;
  return fmt::format(
      "Katsuragi-Durian (pooled, {} samples): g = {:.2f} +- {:.2f} m/s^2, d1 = {:.4f} +- "
      "{:.4f} m (m/d1 = {:.2f} +- {:.2f} kg/m), k = {:.0f} +- {:.0f} N/m\n"
      "  from the DEM force: g = {:.2f}, d1 = {:.4f} m, k = {:.0f} N/m\n"
      "  m/d1 = {:.2f} rho_g A; carried to the lab cylinder: cd = {:.0f} kg/m (catalog "
      "inertial_drag cd in [{}, {}], benchmark truth {})\n",
      f.n, f.g_mps2, f.g_se, f.d1_m, f.d1_se, f.drag_kg_per_m, f.drag_se, f.k_Npm, f.k_se,
      ff.g_mps2, ff.d1_m, ff.k_Npm, c.m_over_d1_over_rho_g_area, c.lab_cylinder_cd_kg_per_m,
      c.cd_lower_kg_per_m, c.cd_upper_kg_per_m, kDetectionBenchmarkDrag_kg_per_m);
}

}  // namespace

InertialDragComparison compare_inertial_drag(const KatsuragiDurianFit& f, double D_sphere_m,
                                             double rho_bulk_kgm3) {
  InertialDragComparison c;
  // The catalog's cd = m / d1 [kg/m]: the bounds of the built-in drag coefficient
  // (ParameterRole::kDragCoefficient), as its effect declares them.
  const ParameterSpec* cd = nullptr;
  const EffectRegistry catalog = EffectRegistry::with_builtins();
  for (const Effect* e : catalog.all())
    for (const ParameterSpec& p : e->parameters())
      if (p.role == ParameterRole::kDragCoefficient) {
        if (cd) throw std::logic_error("two built-in effects declare a drag coefficient");
        cd = &p;
      }
  if (!cd) throw std::logic_error("no built-in effect declares a drag coefficient");
  c.cd_lower_kg_per_m = cd->lower;
  c.cd_upper_kg_per_m = cd->upper;
  // Katsuragi & Durian 2007: m / d1 and k scale with rho_g x the projectile's projected area
  // (pi D_b^2 / 4 for the sphere; the lab cylinder's radius x length, as the detection
  // benchmark's truth takes it).
  const double area = std::numbers::pi / 4 * D_sphere_m * D_sphere_m;
  c.m_over_d1_over_rho_g_area = f.drag_kg_per_m / (rho_bulk_kgm3 * area);
  c.k_over_rho_g_g_area = f.k_Npm / (rho_bulk_kgm3 * kDeckGravity_mps2 * area);
  const Shape lab = Shape::cylinder();
  const auto on_lab_cylinder = [&](double per_area) {
    return per_area * lab.rounding_radius_m * lab.length_m;
  };
  c.lab_cylinder_cd_kg_per_m = on_lab_cylinder(c.m_over_d1_over_rho_g_area * rho_bulk_kgm3);
  c.lab_cylinder_k_Npm = on_lab_cylinder(c.k_over_rho_g_g_area * rho_bulk_kgm3 * kDeckGravity_mps2);
  return c;
}

DropStudyAnalysis analyse_drop_study(std::vector<StudyDrop> drops, double mu, const BedFiles& bed,
                                     const DropStudyAnalysisOptions& options) {
  DropStudyAnalysis a;
  a.mu = mu;
  a.drops = std::move(drops);
  Depths depths;
  std::vector<KdSample> pooled, pooled_force;
  ViscousExtension viscous;
  const double inflation = static_cast<double>(2 * options.analysis.half_window + 1);
  double rho_bulk_sum = 0;
  a.mass_kg = a.rho_sphere_kgm3 = a.D_sphere_m = NAN;
  for (const auto& [row, track] : a.drops) {
    // Uehara et al. 2003 Eq. (1) for this drop's own H and bulk density.
    const double H = row.number("H_total_m");
    a.d_uehara_m.push_back(
        std::isfinite(H) && H > 0
            ? std::optional(uehara_depth_m(H, row.number("rho_sphere"), row.number("rho_bulk"),
                                           row.number("D_sphere_m"), mu))
            : std::nullopt);
    if (!reached_bed(row)) continue;
    if (row.number("depth_max_m") > 0) {
      depths.H_max.push_back(row.number("h_drop_m") + row.number("depth_max_m"));
      depths.d_max.push_back(row.number("depth_max_m"));
    }
    ++a.n_reached;
    a.mass_kg = row.number("mass_kg");
    a.rho_sphere_kgm3 = row.number("rho_sphere");
    a.D_sphere_m = row.number("D_sphere_m");
    rho_bulk_sum += row.number("rho_bulk");
    a.wall_s_sum += row.number("wall_s");
    a.cpu_s_sum += row.number("cpu_s");
    a.grain_steps += row.number("steps") * (row.number("grains") + 1);
    if (row.text("status") == "at_rest") {
      ++a.n_at_rest;
      depths.H.push_back(row.number("H_total_m"));
      depths.d.push_back(row.number("depth_final_m"));
    }
    // The penetration phase twice: z'' from the depth record, and from the contact force.
    const auto s = drop_samples(track, options.analysis, a.mass_kg * kDeckGravity_mps2);
    pooled.insert(pooled.end(), s.begin(), s.end());
    std::optional<ViscousDragFit> own;
    if (s.size() > 10) {
      try {
        own = fit_viscous_katsuragi_durian(s, a.mass_kg, inflation);
      } catch (const std::invalid_argument&) {
        // Collinear or too few samples: this drop has no viscous fit.
      }
    }
    viscous.per_drop.emplace_back(row.text("id"), own);
    for (const auto& x : s)
      pooled_force.push_back({track.depth[x.index], -track.vz[x.index],
                              kDeckGravity_mps2 - track.fcz[x.index] / a.mass_kg, x.index});
  }
  a.rho_bulk_kgm3 = a.n_reached ? rho_bulk_sum / static_cast<double>(a.n_reached) : NAN;
  if (a.n_reached > 0) {
    // Grain size: the middle radius of the bed's three (the mass-weighted mean is within 5 %).
    a.grain_diameter_m = 2 * std::stod(bed.values.count("r2_m") ? bed.values.at("r2_m") : "0");
  }
  // Uehara's law on the resting depths (the check), or on the largest depths when fewer than 3
  // drops stayed in the sand (a diagnostic only: the law is about resting depths).
  if (a.n_at_rest >= 3)
    a.uehara = uehara_outcome(depths, true, a, options.tolerance);
  else if (depths.d_max.size() >= 3)
    a.uehara_largest = uehara_outcome(depths, false, a, options.tolerance);
  a.speed_scaling = speed_scaling(a);
  a.kd_samples = pooled.size();
  if (pooled.size() > 10) {
    a.katsuragi_durian =
        katsuragi_durian_outcome(pooled, pooled_force, a, options.analysis.half_window);
    try {
      viscous.pooled = fit_viscous_katsuragi_durian(pooled, a.mass_kg, inflation);
    } catch (const std::invalid_argument&) {
      // Reported as absent.
    }
    a.viscous = std::move(viscous);
  }
  return a;
}

json to_json(const DropStudyAnalysis& a) {
  json list = json::array();
  for (std::size_t i = 0; i < a.drops.size(); ++i)
    list.push_back(drop_json(a.drops[i], a.d_uehara_m[i]));
  json j = {{"drops", list}};
  if (a.n_reached > 0) {
    const double d_g = a.grain_diameter_m;
    j["sphere"] = {{"D_m", a.D_sphere_m},
                   {"rho_kgm3", a.rho_sphere_kgm3},
                   {"mass_kg", a.mass_kg},
                   {"D_over_grain_diameter", d_g > 0 ? a.D_sphere_m / d_g : NAN}};
    j["rho_bulk_kgm3"] = a.rho_bulk_kgm3;
    const auto n = static_cast<double>(a.n_reached);
    j["cost"] = {
        {"drops", a.n_reached},
        {"wall_s_per_drop", a.wall_s_sum / n},
        {"cpu_s_per_drop", a.cpu_s_sum / n},
        {"core_us_per_grain_step", a.grain_steps > 0 ? 1e6 * a.cpu_s_sum / a.grain_steps : NAN}};
  }
  if (a.uehara) {
    j["uehara"] = uehara_json(*a.uehara, a.mu);
  } else {
    j["uehara"] = {{"pass", false}, {"error", too_few_at_rest(a)}};
    if (a.uehara_largest) j["uehara_largest_depth"] = uehara_json(*a.uehara_largest, a.mu);
  }
  if (a.speed_scaling) j["speed_scaling"] = speed_scaling_json(*a.speed_scaling);
  if (a.katsuragi_durian) j["katsuragi_durian"] = katsuragi_durian_json(*a.katsuragi_durian);
  if (a.viscous) j["viscous_extension"] = viscous_json(*a.viscous);
  return j;
}

std::string to_text(const DropStudyAnalysis& a) {
  const auto number = [](const json& x, const char* k) {
    return x.contains(k) && x[k].is_number() ? x[k].get<double>() : NAN;
  };
  std::string text;
  for (std::size_t i = 0; i < a.drops.size(); ++i) {
    const json x = drop_json(a.drops[i], a.d_uehara_m[i]);
    text +=
        fmt::format("  {:>12} {:>10}  h = {:.3f} m  d = {:.4f} m (Uehara {:.4f} m)  H = {:.4f} m\n",
                    x.value("id", ""), x.value("status", ""), number(x, "h_drop_m"),
                    number(x, "depth_final_m"), number(x, "d_uehara_m"), number(x, "H_total_m"));
  }
  if (a.uehara) {
    text += uehara_text(*a.uehara, a.mu);
  } else {
    text += "Uehara: FAIL, " + too_few_at_rest(a) + "\n";
    if (a.uehara_largest) text += uehara_text(*a.uehara_largest, a.mu);
  }
  if (a.speed_scaling) text += speed_scaling_text(*a.speed_scaling);
  if (a.katsuragi_durian) text += katsuragi_durian_text(*a.katsuragi_durian);
  if (a.viscous) text += viscous_text(*a.viscous);
  return text;
}

}  // namespace ricochet::dem
