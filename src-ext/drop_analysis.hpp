// The analysis of a sphere-drop study (`ricochet dem drop`; docs/granular-impact-checks.md): every
// drop of the study, read back from its results file (drop_store.hpp) or just run, checked
// against granular-impact physics, then its output layer (JSON and text). Pure functions on rows
// and tracks: no LIGGGHTS, no MPI, so they are unit-tested on synthetic drops
// (tests/dem/drop_analysis_test.cpp). The study itself (drops, beds, repose run) is drop_study.hpp.
//
//  - Uehara, Ambroso, Ojha & Durian 2003, PRL 90, 194301, Eq. (1): the resting depth d of the
//    sphere's bottom against the total drop distance H = h + d,
//      d = (0.14 / mu) (rho_b / rho_g)^(1/2) D_b^(2/3) H^(1/3),
//    fitted as d = A H^n (check_uehara, granular_fits.hpp); the check passes when
//    |n - 1/3| <= tolerance.
//  - Katsuragi & Durian 2007, Nature Physics 3, 420, Eq. (1): m z'' = m g - (m / d1) z'^2 - k z
//    over the penetration phases of all drops pooled (fit_katsuragi_durian); m / d1 [kg/m] is
//    the catalog's inertial_drag coefficient cd, whose bounds are read from the effect's
//    declaration (calibration/effects/inertial_drag.cpp), and it is carried to the lab cylinder
//    (data/shapes/cylinder.toml) as m / d1 ~ rho_g x projected area.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drop.hpp"
#include "drop_store.hpp"
#include "granular_fits.hpp"
#include "params.hpp"

namespace ricochet::dem {

/// The detection benchmark's truth for the lab cylinder's drag, m / d1 = 40 kg/m (Katsuragi &
/// Durian 2007: rho_g x projected area = 1600 kg/m^3 x 0.08 m x 0.29 m; its one definition is
/// the independent simulator, tests/detection/truth_sim.hpp, docs/detection-benchmark.md) [kg/m].
inline constexpr double kDetectionBenchmarkDrag_kg_per_m = 40.0;

/// One drop of a study: its stored row (drop_row_names()) and its track (empty when the file of
/// tracks is missing: the drop then has no Katsuragi-Durian samples).
struct StudyDrop {
  DropRow row;
  DropTrack track;
};

/// How a study is analysed.
struct DropStudyAnalysisOptions {
  DropAnalysisOptions analysis;  ///< derivative window and end of the penetration phase
  double tolerance = UeharaCheck{}.tolerance;  ///< largest |n - 1/3| that passes Uehara's check
};

/// Uehara's law fitted on one set of depths.
struct UeharaOutcome {
  std::string depth;  ///< "resting" (the check) or "largest" (a diagnostic only)
  bool is_check = false;
  std::optional<UeharaCheck> check;  ///< empty when the fit failed
  std::string error;                 ///< why it failed
};

/// The pooled Katsuragi-Durian fit set against the catalog's inertial_drag.
struct InertialDragComparison {
  double cd_lower_kg_per_m = 0, cd_upper_kg_per_m = 0;  ///< inertial_drag's declared cd bounds
  double m_over_d1_over_rho_g_area = 0;  ///< the sphere's m / d1 over rho_g x pi D_b^2 / 4 [-]
  double k_over_rho_g_g_area = 0;        ///< its k over rho_g g x pi D_b^2 / 4 [1/m]
  double lab_cylinder_cd_kg_per_m = 0;   ///< the first x rho_g x the lab cylinder's R x L
  double lab_cylinder_k_Npm = 0;         ///< the second x rho_g g x R x L
};

/// Katsuragi & Durian 2007 on the pooled penetration samples (more than 10), with the variances
/// inflated by the derivative window (2 half_window + 1 records).
struct KatsuragiDurianOutcome {
  std::optional<KatsuragiDurianFit> trajectory;  ///< z'' from the depth record
  std::optional<KatsuragiDurianFit> force;       ///< z'' = g - F_z / m from the contact force
  std::optional<KatsuragiDurianFit> g_fixed;     ///< trajectory with g imposed (kDeckGravity_mps2)
  std::optional<InertialDragComparison> inertial_drag;
  std::string error;  ///< why a fit failed (then no fit is reported)
};

/// The resting depth against the impact speed, d = A v^n over the drops at rest (issue 32's
/// stiff bed, docs/granular-impact-checks.md), beside the two exponents it is read against at the
/// same drops: Uehara's law, d = C' (h + d)^(1/3) with C' its resting fit's, solved at each
/// drop's h and fitted against the same speeds (about 2/3 when h >> d, less when d is not small
/// against h); and a deceleration proportional to the impact speed with a stopping time
/// independent of it (Pica Ciamarra et al. 2004, PRL 92, 194301; Tsimring & Volfson 2005),
/// d ~ v, n = 1. With the ranges of d / v and of the penetration phase's duration (the latter
/// constant in that regime).
struct SpeedScaling {
  PowerLawFit fit;               ///< d [m] = A v^n, v the impact speed [m/s]
  double uehara_exponent = NAN;  ///< n of Uehara's law at the same drops
  double d_over_v_min_s = NAN, d_over_v_max_s = NAN;
  double t_penetration_min_s = NAN, t_penetration_max_s = NAN;
};

/// The viscous extension of Katsuragi-Durian (fit_viscous_katsuragi_durian), drop by drop and
/// pooled: exploratory, not part of the check (docs/granular-impact-checks.md, "On the stiff
/// bed"). Per drop: its id and the fit, empty where it failed.
struct ViscousExtension {
  std::vector<std::pair<std::string, std::optional<ViscousDragFit>>> per_drop;
  std::optional<ViscousDragFit> pooled;
};

/// What a study concludes. Sphere, bulk density and cost come from the drops that reached the
/// bed (status at_rest or rebound; the sphere's from the last of them); NaN without any.
struct DropStudyAnalysis {
  double mu = 0;  ///< tan(angle of repose), imposed or measured
  std::vector<StudyDrop> drops;
  std::vector<std::optional<double>> d_uehara_m;  ///< per drop, Uehara's depth for its H [m]
  std::size_t n_reached = 0;                      ///< drops at rest or rebounding
  std::size_t n_at_rest = 0;
  double mass_kg = 0, rho_sphere_kgm3 = 0, D_sphere_m = 0;
  double rho_bulk_kgm3 = 0;     ///< mean over the drops that reached the bed
  double grain_diameter_m = 0;  ///< 2 x the bed's middle radius r2_m (0 when unknown)
  double wall_s_sum = 0, cpu_s_sum = 0;
  double grain_steps = 0;  ///< sum of steps x (grains + 1)
  /// Uehara on the resting depths when at least 3 drops came to rest, else empty (the check
  /// fails) and `uehara_largest` on the largest depths when at least 3 drops reached the bed.
  std::optional<UeharaOutcome> uehara, uehara_largest;
  /// With at least 3 drops at rest that have an impact speed and Uehara's resting fit.
  std::optional<SpeedScaling> speed_scaling;
  std::size_t kd_samples = 0;                              ///< pooled penetration samples
  std::optional<KatsuragiDurianOutcome> katsuragi_durian;  ///< with more than 10 samples
  std::optional<ViscousExtension> viscous;                 ///< with it
};

/// Analyses every drop of a study with friction `mu`; `bed` is the study's bed (its r2_m gives
/// the grain diameter). Fit failures are recorded, not thrown.
DropStudyAnalysis analyse_drop_study(std::vector<StudyDrop> drops, double mu, const BedFiles& bed,
                                     const DropStudyAnalysisOptions& options);

/// The catalog's inertial_drag against the pooled fit `f` of spheres of diameter D_b [m] in a
/// bed of bulk density rho_g [kg/m^3]: the bounds from the effect registry, the lab cylinder's
/// radius and length from Shape::cylinder() (data/shapes/cylinder.toml).
InertialDragComparison compare_inertial_drag(const KatsuragiDurianFit& f, double D_sphere_m,
                                             double rho_bulk_kgm3);

/// The output layer: the analysis's keys of the `ricochet dem drop --json` document (drops with
/// d_uehara_m, sphere, rho_bulk_kgm3, cost, uehara, uehara_largest_depth, katsuragi_durian;
/// speed_scaling, viscous_extension; docs/commands/dem.md; mu is the friction's, drop_study.hpp),
/// and its readable summary (one line per drop, then the checks).
nlohmann::json to_json(const DropStudyAnalysis& a);
std::string to_text(const DropStudyAnalysis& a);

}  // namespace ricochet::dem
