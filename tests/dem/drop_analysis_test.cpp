// The analysis of a sphere-drop study (src-ext/drop_analysis.hpp) on synthetic drops whose
// answers are known beforehand: resting depths made with Uehara's law and a chosen prefactor,
// Katsuragi-Durian penetrations integrated by RK4 with a chosen d1 and k, and the per-drop
// quantities, the inertial_drag comparison and the JSON summary worked out by hand here. No
// LIGGGHTS.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/csv.hpp"
#include "drop_analysis.hpp"
#include "effects/registry.hpp"
#include "rk4_penetration.hpp"

namespace {

using namespace ricochet::dem;
using ricochet::shortest_number;

constexpr double kG = 9.81;
constexpr double kD = 0.05, kRhoSphere = 7800, kRhoBulk = 1600, kMu = 0.6;
const double kMass = kRhoSphere * std::numbers::pi / 6 * kD * kD * kD;

// The study's id of height h: "h0.2" (GCC 12 warns, wrongly, on "h" + a temporary string).
std::string id_of(double h) {
  std::string id = "h";
  id += shortest_number(h);
  return id;
}

BedFiles bed_with_r2(double r2_m) {
  BedFiles b;
  b.values["r2_m"] = shortest_number(r2_m);
  return b;
}

// A stored drop: the cells the analysis reads (drop_row_names()), "nan" where a failed drop
// has no value.
StudyDrop drop(const std::string& id, const std::string& status, double h, double d_final,
               double d_max) {
  StudyDrop s;
  const bool reached = status == "at_rest" || status == "rebound";
  auto cell = [&](const std::string& name, double v) {
    s.row.cells[name] = std::isfinite(v) ? shortest_number(v) : "nan";
  };
  s.row.cells["id"] = id;
  s.row.cells["status"] = status;
  cell("h_drop_m", h);
  cell("depth_final_m", reached ? d_final : NAN);
  cell("depth_max_m", reached ? d_max : NAN);
  cell("H_total_m", reached ? h + d_final : NAN);
  cell("D_sphere_m", kD);
  cell("rho_sphere", kRhoSphere);
  cell("mass_kg", kMass);
  cell("rho_bulk", kRhoBulk);
  cell("wall_s", 10);
  cell("cpu_s", 8);
  cell("steps", 1000);
  cell("grains", 99);
  return s;
}

// Uehara's law with prefactor C in place of 0.14 / mu: d = C (rho_b / rho_g)^(1/2) D^(2/3) H^(1/3),
// solved for d at a given h (H = h + d) by fixed-point iteration.
double uehara_rest_depth(double C, double h) {
  const double scale = std::pow(kRhoSphere / kRhoBulk, 0.5) * std::pow(kD, 2.0 / 3.0);
  double d = 0;
  for (int i = 0; i < 200; ++i) d = C * scale * std::pow(h + d, 1.0 / 3.0);
  return d;
}

TEST(DropAnalysis, UeharaOnRestingDepthsRecoversThePrefactor) {
  const double C = 0.5 * 0.14 / kMu;  // a bed half as deep as Uehara's
  std::vector<StudyDrop> drops;
  for (double h : {0.05, 0.1, 0.2, 0.5, 1.0}) {
    const double d = uehara_rest_depth(C, h);
    drops.push_back(drop(id_of(h), "at_rest", h, d, 1.2 * d));
  }
  drops.push_back(drop("h2", "timeout", 2.0, NAN, NAN));
  const auto a = analyse_drop_study(drops, kMu, bed_with_r2(0.0035), {});
  EXPECT_EQ(a.n_reached, 5u);
  EXPECT_EQ(a.n_at_rest, 5u);
  ASSERT_TRUE(a.uehara && a.uehara->check) << (a.uehara ? a.uehara->error : "no check");
  EXPECT_FALSE(a.uehara_largest);
  EXPECT_NEAR(a.uehara->check->fit.exponent, 1.0 / 3.0, 1e-9);
  EXPECT_NEAR(a.uehara->check->c_fitted / C, 1.0, 1e-9);
  EXPECT_TRUE(a.uehara->check->exponent_pass);
  // Each drop's Uehara depth for its own H, the prefactor 0.14 / mu; none for the failed one.
  ASSERT_EQ(a.d_uehara_m.size(), 6u);
  const double H = 0.2 + uehara_rest_depth(C, 0.2);
  EXPECT_NEAR(*a.d_uehara_m[2],
              0.14 / kMu * std::sqrt(kRhoSphere / kRhoBulk) * std::pow(kD * kD, 1.0 / 3.0) *
                  std::pow(H, 1.0 / 3.0),
              1e-12);
  EXPECT_FALSE(a.d_uehara_m[5]);

  const auto j = to_json(a);
  EXPECT_EQ(j["drops"].size(), 6u);
  EXPECT_TRUE(j["drops"][5]["depth_final_m"].is_null());
  EXPECT_EQ(j["drops"][5]["status"], "timeout");
  EXPECT_EQ(j["uehara"]["pass"], true);
  EXPECT_EQ(j["uehara"]["depth"], "resting");
  EXPECT_NEAR(j["uehara"]["C_ratio"].get<double>(), 0.5, 1e-9);
  EXPECT_NEAR(j["uehara"]["C_fitted_times_mu"].get<double>(), 0.07, 1e-9);
  EXPECT_NEAR(j["sphere"]["D_over_grain_diameter"].get<double>(), kD / 0.007, 1e-12);
  EXPECT_EQ(j["cost"]["drops"], 5u);
  EXPECT_DOUBLE_EQ(j["cost"]["wall_s_per_drop"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(j["cost"]["core_us_per_grain_step"].get<double>(), 1e6 * 8 / (1000 * 100));
  EXPECT_FALSE(j.contains("katsuragi_durian"));  // no track, no penetration sample
  EXPECT_NE(to_text(a).find("resting depths (d ~ H^n, 5 drops): n = 0.333"), std::string::npos);
}

// The depth against the impact speed: on drops that follow Uehara's law its exponent is the one
// Uehara's law gives at the same drops (below 2/3, since d is not small against h at 5 cm); on
// drops with d = 20 ms x v (a deceleration proportional to the impact speed) it is 1, with d / v 20
// ms; the penetration phase's range is the rows' own.
TEST(DropAnalysis, DepthAgainstImpactSpeedIsReadAgainstUeharaAndAConstantStoppingTime) {
  const double C = 0.5 * 0.14 / kMu;
  std::vector<StudyDrop> uehara, linear;
  for (double h : {0.02, 0.05, 0.1, 0.2, 0.5}) {
    const double v = std::sqrt(2 * kG * h);
    uehara.push_back(drop(id_of(h), "at_rest", h, uehara_rest_depth(C, h), NAN));
    linear.push_back(drop(id_of(h), "at_rest", h, 0.020 * v, NAN));
    for (auto* d : {&uehara.back(), &linear.back()}) {
      d->row.cells["v_impact_mps"] = shortest_number(v);
      d->row.cells["t_penetration_s"] = shortest_number(0.04 + 0.01 * h);
    }
  }
  const auto a = analyse_drop_study(uehara, kMu, bed_with_r2(0.0035), {});
  ASSERT_TRUE(a.speed_scaling);
  EXPECT_NEAR(a.speed_scaling->fit.exponent, a.speed_scaling->uehara_exponent, 1e-9);
  EXPECT_GT(a.speed_scaling->uehara_exponent, 0.4);
  EXPECT_LT(a.speed_scaling->uehara_exponent, 2.0 / 3.0 - 0.02);
  const auto b = analyse_drop_study(linear, kMu, bed_with_r2(0.0035), {});
  ASSERT_TRUE(b.speed_scaling);
  EXPECT_NEAR(b.speed_scaling->fit.exponent, 1.0, 1e-9);
  EXPECT_NEAR(b.speed_scaling->d_over_v_min_s, 0.020, 1e-12);
  EXPECT_NEAR(b.speed_scaling->d_over_v_max_s, 0.020, 1e-12);
  EXPECT_LT(b.speed_scaling->uehara_exponent, 2.0 / 3.0);
  EXPECT_NEAR(b.speed_scaling->t_penetration_min_s, 0.0402, 1e-12);
  EXPECT_NEAR(b.speed_scaling->t_penetration_max_s, 0.045, 1e-12);
  const auto j = to_json(b);
  EXPECT_NEAR(j["speed_scaling"]["exponent"].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(j["speed_scaling"]["drops"], 5u);
  EXPECT_NE(to_text(b).find("Depth against impact speed (d ~ v^n, 5 drops at rest): n = 1.000"),
            std::string::npos)
      << to_text(b);
  // Without an impact speed (older files), no speed scaling.
  EXPECT_FALSE(
      analyse_drop_study({drop("h1", "at_rest", 0.1, 0.02, 0.02)}, kMu, {}, {}).speed_scaling);
}

TEST(DropAnalysis, FewerThanThreeAtRestFailsAndFitsTheLargestDepths) {
  std::vector<StudyDrop> drops = {
      drop("h0.05", "rebound", 0.05, -1e-4, 0.002), drop("h0.1", "rebound", 0.1, 1e-4, 0.003),
      drop("h0.2", "rebound", 0.2, 2e-4, 0.004), drop("h0.5", "at_rest", 0.5, 0.004, 0.006),
      drop("h1", "bottom", 1.0, NAN, NAN)};
  const auto a = analyse_drop_study(drops, kMu, bed_with_r2(0.0035), {});
  EXPECT_EQ(a.n_reached, 4u);
  EXPECT_EQ(a.n_at_rest, 1u);
  EXPECT_FALSE(a.uehara);
  ASSERT_TRUE(a.uehara_largest && a.uehara_largest->check);
  EXPECT_FALSE(a.uehara_largest->is_check);
  EXPECT_EQ(a.uehara_largest->check->fit.n, 4u);  // the four largest depths, H = h + d_max
  const auto j = to_json(a);
  EXPECT_EQ(j["uehara"]["pass"], false);
  EXPECT_NE(j["uehara"]["error"].get<std::string>().find("1 of 5 drops came to rest"),
            std::string::npos);
  EXPECT_EQ(j["uehara_largest_depth"]["depth"], "largest");
  EXPECT_EQ(j["uehara_largest_depth"]["pass"], false);  // a diagnostic never passes
  const std::string text = to_text(a);
  EXPECT_NE(text.find("Uehara: FAIL, 1 of 5 drops"), std::string::npos) << text;
  EXPECT_NE(text.find("diagnostic only"), std::string::npos) << text;
}

// A drop's track: free fall onto the surface at speed v0, then Katsuragi & Durian's
// m z'' = m g - (m / d1) z'^2 - k z (z the depth, positive down), RK4 at 1 us, recorded every
// 20 us until the sphere stops; the contact force F_z = m (g - z'') is what the DEM records.
DropTrack kd_track(double v0, double d1, double k) {
  auto acc = [&](double z, double v) { return z < 0 ? kG : kG - v * v / d1 - k / kMass * z; };
  DropTrack tr;
  const double dt = 1e-6;
  double z = -v0 * 0.003, v = v0, t = 0;
  for (long i = 0; v > 0; ++i) {
    if (i % 20 == 0) {
      tr.t.push_back(t);
      tr.depth.push_back(z);
      tr.vz.push_back(-v);
      tr.fcz.push_back(kMass * (kG - acc(z, v)));
    }
    test::rk4_step(z, v, dt, acc);
    t += dt;
  }
  for (auto* c : {&tr.x, &tr.y, &tr.vx, &tr.vy, &tr.fcx, &tr.fcy, &tr.ke_grains})
    c->assign(tr.t.size(), 0.0);
  return tr;
}

// The viscous extension (exploratory): drops integrated by RK4 with a viscous force b z' beside
// Katsuragi-Durian's terms give back b, m / d1 and k pooled and g in each drop, where the plain
// Katsuragi-Durian fit of the same drops cannot (its g leaves 9.81 by more than 2 m/s^2).
TEST(DropAnalysis, TheViscousExtensionRecoversALinearDragThatKatsuragiDurianCannotHold) {
  const double b = 60.0, d1 = 0.02, k = 2e4;  // b / m = 118 1/s: stops of about 20 ms
  auto acc = [&](double z, double v) {
    return z < 0 ? kG : kG - b / kMass * v - v * v / d1 - k / kMass * z;
  };
  std::vector<StudyDrop> drops;
  for (double h : {0.05, 0.2, 0.5}) {
    StudyDrop s = drop(id_of(h), "at_rest", h, 0.02, 0.021);
    double z = -0.001, v = std::sqrt(2 * kG * h), t = 0;
    for (long i = 0; v > 0; ++i) {
      if (i % 20 == 0) {
        s.track.t.push_back(t);
        s.track.depth.push_back(z);
        s.track.vz.push_back(-v);
        s.track.fcz.push_back(kMass * (kG - acc(z, v)));
      }
      test::rk4_step(z, v, 1e-6, acc);
      t += 1e-6;
    }
    for (auto* c : {&s.track.x, &s.track.y, &s.track.vx, &s.track.vy, &s.track.fcx, &s.track.fcy,
                    &s.track.ke_grains})
      c->assign(s.track.t.size(), 0.0);
    drops.push_back(std::move(s));
  }
  const auto a = analyse_drop_study(drops, kMu, bed_with_r2(0.0035), {});
  ASSERT_TRUE(a.viscous && a.viscous->pooled);
  const auto& p = *a.viscous->pooled;
  EXPECT_NEAR(p.b_Nspm / b, 1.0, 0.02);
  EXPECT_NEAR(p.drag_kg_per_m / (kMass / d1), 1.0, 0.02);
  EXPECT_NEAR(p.k_Npm / k, 1.0, 0.05);
  EXPECT_NEAR(p.g_mps2, kG, 0.2);
  ASSERT_EQ(a.viscous->per_drop.size(), 3u);
  for (const auto& [id, f] : a.viscous->per_drop) {
    ASSERT_TRUE(f) << id;
    EXPECT_NEAR(f->g_mps2, kG, 0.5) << id;
  }
  ASSERT_TRUE(a.katsuragi_durian && a.katsuragi_durian->trajectory);
  EXPECT_GT(std::abs(a.katsuragi_durian->trajectory->g_mps2 - kG), 2.0);
  const auto j = to_json(a)["viscous_extension"];
  EXPECT_EQ(j["exploratory"], true);
  EXPECT_NEAR(j["pooled"]["time_constant_s"].get<double>(), kMass / b, 0.02 * kMass / b);
  EXPECT_NE(to_text(a).find("Katsuragi-Durian + viscous b z' (exploratory)"), std::string::npos);
}

TEST(DropAnalysis, PooledKatsuragiDurianRecoversDragAndCarriesItToTheLabCylinder) {
  const double d1 = 0.01, k = 5e4;  // m / d1 = 51 kg/m
  std::vector<StudyDrop> drops;
  for (double h : {0.1, 0.2, 0.5}) {
    StudyDrop s = drop(id_of(h), "at_rest", h, 0.02, 0.021);
    s.track = kd_track(std::sqrt(2 * kG * h), d1, k);
    drops.push_back(std::move(s));
  }
  const auto a = analyse_drop_study(drops, kMu, bed_with_r2(0.0035), {});
  ASSERT_TRUE(a.katsuragi_durian);
  const auto& kd = *a.katsuragi_durian;
  ASSERT_TRUE(kd.trajectory && kd.force && kd.g_fixed && kd.inertial_drag) << kd.error;
  EXPECT_GT(a.kd_samples, 300u);
  // From the depth record (derivatives of z(t)): within 1 %.
  EXPECT_NEAR(kd.trajectory->d1_m / d1, 1.0, 0.01);
  EXPECT_NEAR(kd.trajectory->k_Npm / k, 1.0, 0.01);
  EXPECT_NEAR(kd.trajectory->g_mps2, kG, 0.1);
  EXPECT_NEAR(kd.g_fixed->d1_m / d1, 1.0, 0.01);
  // From the contact force, z'' = g - F_z / m exactly: to rounding.
  EXPECT_NEAR(kd.force->d1_m / d1, 1.0, 1e-8);
  EXPECT_NEAR(kd.force->k_Npm / k, 1.0, 1e-8);
  // Carried to the lab cylinder (R 0.08 m, L 0.29 m, data/shapes/cylinder.toml):
  // cd = (m / d1) / (rho_g pi D^2 / 4) x rho_g R L.
  const auto& c = *kd.inertial_drag;
  const double m_over_d1 = kd.trajectory->drag_kg_per_m;
  EXPECT_NEAR(c.lab_cylinder_cd_kg_per_m,
              m_over_d1 * 0.08 * 0.29 / (std::numbers::pi / 4 * kD * kD), 1e-9 * m_over_d1);
  EXPECT_NEAR(c.lab_cylinder_k_Npm,
              kd.trajectory->k_Npm * 0.08 * 0.29 / (std::numbers::pi / 4 * kD * kD), 1e-9 * k);
  // The bounds are inertial_drag's own.
  const auto catalog = ricochet::EffectRegistry::with_builtins();
  const auto& cd = catalog.get("inertial_drag").parameters()[0];
  EXPECT_EQ(cd.name, "cd");
  EXPECT_EQ(c.cd_lower_kg_per_m, cd.lower);
  EXPECT_EQ(c.cd_upper_kg_per_m, cd.upper);
  const auto j = to_json(a)["katsuragi_durian"];
  EXPECT_EQ(j["inertial_drag"]["cd_bounds_kg_per_m"][1], cd.upper);
  EXPECT_EQ(j["inertial_drag"]["cd_detection_benchmark_kg_per_m"], 40.0);
  EXPECT_EQ(j["trajectory"]["variance_inflation"], 21.0);  // 2 half_window + 1
  // The text as it was when the bounds were written into it: "[0, 5000]".
  EXPECT_NE(to_text(a).find("catalog inertial_drag cd in [0, 5000], benchmark truth 40"),
            std::string::npos)
      << to_text(a);
}

}  // namespace
