#include "truth_sim.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace ricochet::truth {
namespace {

// Reference strengths (s = 1), header comment and docs/detection-benchmark.md.
constexpr double kVc = 9.144;  // CRSP v_c [m/s] (Pfeiffer & Bowen 1989)
constexpr double kDragRef =
    40.0;  // Katsuragi-Durian m/d1 for the lab cylinder [kg/m] (truth_sim.hpp)
constexpr double kSpinRef = 0.008;  // c_w [s/rad], lab scale at s = 1 (no literature value)
constexpr double kDepthRef = 3e-3;  // h_mu [m] (no literature value)
constexpr double kDepthSpeedRef = kDragRef / kDepthRef;  // c_hv [kg/m^2]: m/d1 at 3 mm
constexpr double kYieldSpeed = 2.0;  // v_yield [m/s] (Thornton & Ning 1998 form; lab-range choice)
constexpr double kSlipSpinRef =
    2e-3;  // c_sw [s^2/(m rad)]: mu +30 % at the lab mean state (no value)
constexpr double kKp = 3.7, kGamma = 15.7e3;  // Rankine K_p (phi = 35 deg), unit weight [N/m^3]
constexpr double kRateDragRef = 100.0;        // c_rt [kg/m] (truth_sim.hpp; no literature value)
constexpr double kRateThreshold = 2.0;        // v_th [m/s]
constexpr double kPloughRef = 0.5 * kKp * kGamma * kLength;  // [N/m^2], times h^2

// Scatter of the ground per release and measurement noise (header comment).
constexpr double kTrackInterval_s = 2e-4;  // a record every 0.2 ms (SetOptions::tracks)
constexpr std::array<double, 3> kNoiseIn = {0.05, 0.05, 1.4}, kNoiseOut = {0.05, 0.03, 2.0};

const std::vector<std::string> kNames = {"none",
                                         "crsp_restitution",
                                         "kd_drag",
                                         "spin_rolling",
                                         "depth_friction_exp",
                                         "rankine_plough",
                                         "two",
                                         "depth_speed_drag",
                                         "yield_restitution",
                                         "slip_spin_friction",
                                         "rate_threshold_drag"};

bool has(const Ground& g, Family f) {
  return g.family == f ||
         (g.family == Family::kTwo && (f == Family::kCrspRestitution || f == Family::kSpinRolling));
}

struct Rng {
  std::mt19937_64 engine;
  explicit Rng(std::uint64_t seed) : engine(seed) {}
  double uniform() {  // [0, 1) from the top 53 bits: the same on every platform
    return static_cast<double>(engine() >> 11) * 0x1.0p-53;
  }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  double normal() {  // Box-Muller, one value per pair of uniforms (no cached second value)
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
};

// Nelder-Mead on a few variables (the refit of the paper's constants in make_set): small, fixed
// iteration count, deterministic.
template <class F>
std::vector<double> nelder_mead(F f, std::vector<double> x0, const std::vector<double>& step,
                                int iterations) {
  const std::size_t d = x0.size();
  std::vector<std::vector<double>> p(d + 1, x0);
  std::vector<double> v(d + 1);
  for (std::size_t i = 0; i < d; ++i) p[i + 1][i] += step[i];
  for (std::size_t i = 0; i <= d; ++i) v[i] = f(p[i]);
  for (int it = 0; it < iterations; ++it) {
    std::vector<std::size_t> o(d + 1);
    for (std::size_t i = 0; i <= d; ++i) o[i] = i;
    std::sort(o.begin(), o.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
    const std::size_t best = o[0], worst = o[d], second = o[d - 1];
    std::vector<double> c(d, 0.0);
    for (std::size_t i = 0; i <= d; ++i)
      if (i != worst)
        for (std::size_t k = 0; k < d; ++k) c[k] += p[i][k] / static_cast<double>(d);
    auto along = [&](double t) {
      std::vector<double> x(d);
      for (std::size_t k = 0; k < d; ++k) x[k] = c[k] + t * (p[worst][k] - c[k]);
      return x;
    };
    const auto xr = along(-1.0);
    const double fr = f(xr);
    if (fr < v[best]) {
      const auto xe = along(-2.0);
      const double fe = f(xe);
      if (fe < fr) {
        p[worst] = xe, v[worst] = fe;
      } else {
        p[worst] = xr, v[worst] = fr;
      }
    } else if (fr < v[second]) {
      p[worst] = xr, v[worst] = fr;
    } else {
      const auto xc = along(fr < v[worst] ? -0.5 : 0.5);
      const double fc = f(xc);
      if (fc < std::min(fr, v[worst])) {
        p[worst] = xc, v[worst] = fc;
      } else {  // shrink towards the best vertex
        for (std::size_t i = 0; i <= d; ++i) {
          if (i == best) continue;
          for (std::size_t k = 0; k < d; ++k) p[i][k] = p[best][k] + 0.5 * (p[i][k] - p[best][k]);
          v[i] = f(p[i]);
        }
      }
    }
  }
  return p[std::min_element(v.begin(), v.end()) - v.begin()];
}

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;  // [row k][column j]

// d V_out / d p_j by central differences of collide(): at(j, h) is the collision with parameter j
// moved by h; a side without a rebound falls back to the one-sided difference with `centre`.
template <class At>
Mat3 central_jacobian(const Rebound& centre, const Vec3& step, At at) {
  Mat3 jac{};
  for (int j = 0; j < 3; ++j) {
    const Rebound plus = at(j, step[j]), minus = at(j, -step[j]);
    const Rebound& p = plus.ok ? plus : centre;
    const Rebound& m = minus.ok ? minus : centre;
    const double width = (plus.ok ? step[j] : 0.0) + (minus.ok ? step[j] : 0.0);
    for (int k = 0; k < 3; ++k) jac[k][j] = width > 0 ? (p.vout[k] - m.vout[k]) / width : 0.0;
  }
  return jac;
}

// The oracle's z (truth_sim.hpp, "The oracle's ceiling", [1]): the whitened effect's norm after
// projecting out what a common change of (e_n^2, mu, mu_R) can produce. Per release: the true
// V_in, the release's ground without the effect, its V_out and the effect delta_i.
double oracle_z(const std::vector<Vec3>& vins, const std::vector<Ground>& grounds,
                const std::vector<Rebound>& nulls, const std::vector<Vec3>& deltas,
                const Numerics& num, const Vec3& lo, const Vec3& hi) {
  Vec3 scatter_var{}, ground_step{}, vin_step{};
  for (int j = 0; j < 3; ++j) {
    scatter_var[j] = (hi[j] - lo[j]) * (hi[j] - lo[j]) / 12.0;  // variance of U(a, b)
    ground_step[j] = 0.02 * (hi[j] - lo[j]);
    vin_step[j] = 0.2 * kNoiseIn[j];
  }
  const auto rows = static_cast<Eigen::Index>(3 * vins.size());
  Eigen::VectorXd d(rows);
  Eigen::MatrixXd x(rows, 3);  // X: the constants' directions
  for (std::size_t i = 0; i < vins.size(); ++i) {
    const Mat3 g = central_jacobian(nulls[i], ground_step, [&](int j, double h) {
      Ground moved = grounds[i];
      double* constant[] = {&moved.en2, &moved.mu, &moved.muR};
      *constant[j] += h;
      return collide(vins[i], moved, num);
    });
    const Mat3 jin = central_jacobian(nulls[i], vin_step, [&](int j, double h) {
      Vec3 moved = vins[i];
      moved[j] += h;
      return collide(moved, grounds[i], num);
    });
    Eigen::Matrix3d G, Jin, sigma;  // [1]
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) G(k, j) = g[k][j], Jin(k, j) = jin[k][j];
    sigma = G * Eigen::Vector3d(scatter_var[0], scatter_var[1], scatter_var[2]).asDiagonal() *
                G.transpose() +
            Jin *
                Eigen::Vector3d(kNoiseIn[0], kNoiseIn[1], kNoiseIn[2])
                    .array()
                    .square()
                    .matrix()
                    .asDiagonal() *
                Jin.transpose();
    for (int k = 0; k < 3; ++k) sigma(k, k) += kNoiseOut[k] * kNoiseOut[k];
    // Whitening by L^-1, Sigma_i = L L^T (N_out makes Sigma_i positive definite).
    const Eigen::LLT<Eigen::Matrix3d> llt(sigma);
    const auto r0 = static_cast<Eigen::Index>(3 * i);
    d.segment<3>(r0) =
        llt.matrixL().solve(Eigen::Vector3d(deltas[i][0], deltas[i][1], deltas[i][2]));
    x.block<3, 3>(r0, 0) = llt.matrixL().solve(G);
  }
  // d_perp = (I - X X^+) d: the least-squares residual of d on X (a pseudo-inverse: a column in
  // the others' span is harmless).
  const Eigen::VectorXd d_perp = d - x * x.completeOrthogonalDecomposition().solve(d);
  return d_perp.norm();
}

}  // namespace

double oracle_power(double z, double alpha) {
  if (!(alpha > 0 && alpha < 1))
    throw std::invalid_argument("oracle_power: alpha must be in (0, 1)");
  // Upper tail Q(x) = erfc(x / sqrt 2) / 2 decreases in x; bisect Q(x) = alpha (erfc keeps the
  // tail's relative accuracy at small alpha).
  auto tail = [](double v) { return 0.5 * std::erfc(v / std::sqrt(2.0)); };
  double lo = -40, hi = 40;
  for (int i = 0; i < 200 && hi - lo > 1e-13; ++i) {
    const double mid = 0.5 * (lo + hi);
    (tail(mid) > alpha ? lo : hi) = mid;
  }
  const double z_alpha = 0.5 * (lo + hi);  // z_{1-alpha}
  return tail(z_alpha - z);                // Phi(z - z_{1-alpha}) = Q(z_{1-alpha} - z), [2]
}

const std::vector<std::string>& family_names() {
  return kNames;
}

const std::string& family_name(Family f) {
  return kNames.at(static_cast<std::size_t>(f));
}

Family family_from_name(const std::string& name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return static_cast<Family>(i);
  std::string list;
  for (const auto& n : kNames) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown family '" + name + "'; accepted: " + list);
}

Reference reference(Family f) {
  switch (f) {
    case Family::kCrspRestitution:
      return {"v_c", kVc, "m/s",
              "v_c = 9.144 m/s (30 ft/s; CRSP, Pfeiffer & Bowen 1989; RocFall's velocity scaling)"};
    case Family::kKdDrag:
      return {"m/d1", kDragRef, "kg/m",
              "m/d1 ~ rho_g x projected area ~ 40 kg/m for this cylinder at 1 cm (Katsuragi & "
              "Durian 2007)"};
    case Family::kSpinRolling:
      return {"c_w", kSpinRef, "s/rad",
              "no literature value; chosen so that s = 1 shifts the mean V_out by the lab's "
              "Table 1 scale on the lab design"};
    case Family::kDepthFrictionExp:
      return {"h_mu", kDepthRef, "m",
              "no literature value (scarring laws give no number for sand); 3 mm = the overlap "
              "scale of the paper's stiffness"};
    case Family::kRankinePlough:
      return {"1/2 K_p gamma L", kPloughRef, "N/m^2 (times h^2)",
              "Rankine passive pressure, K_p = 3.7 (phi = 35 deg), gamma = 15.7 kN/m^3, "
              "L = 0.29 m: 1 N at h = 1 cm"};
    case Family::kTwo:
      return {"", 0, "", "crsp_restitution and spin_rolling, each at s times its reference"};
    case Family::kDepthSpeedDrag:
      return {"c_hv", kDepthSpeedRef, "kg/m^2",
              "Katsuragi-Durian's m/d1 = 40 kg/m reached at 3 mm of overlap (no literature value "
              "for the depth dependence)"};
    case Family::kYieldRestitution:
      return {"v_yield", kYieldSpeed, "m/s",
              "e ~ (v_yield / v)^(1/4) above the yield speed at s = 1 (Thornton & Ning 1998, "
              "elastic-plastic impact); 2 m/s a lab-range choice"};
    case Family::kSlipSpinFriction:
      return {"c_sw", kSlipSpinRef, "s^2/(m rad)", "no literature value"};
    case Family::kRateThresholdDrag:
      return {"c_rt", kRateDragRef, "kg/m (times (|v_y| - 2 m/s)^2)",
              "no literature value; 400 N at 4 m/s, as the Katsuragi-Durian drag's 40 kg/m at "
              "3.2 m/s"};
    default:
      return {"", 0, "", "none"};
  }
}

std::string reference_strength(Family f) {
  const Reference r = reference(f);
  if (r.parameter.empty()) return r.literature;
  char v[32];
  std::snprintf(v, sizeof v, "%g", r.value);
  return r.parameter + " = " + v + " " + r.unit + " (" + r.literature + ")";
}

std::string candidate_family(const std::string& e) {
  auto starts = [&](const char* p) { return e.rfind(p, 0) == 0; };
  if (e == "rate_restitution" || starts("en2_")) return "restitution";
  if (e == "inertial_drag") return "drag";
  if (starts("muR_spin_")) return "spin rolling";
  if (e == "depth_friction" || starts("mu_penetration_")) return "depth friction";
  if (starts("mu_slip_speed_") || starts("mu_spin_")) return "slip friction";
  if (e == "ploughing") return "ploughing";
  return "other";
}

std::vector<std::string> expected_families(Family f) {
  switch (f) {
    case Family::kCrspRestitution:
      return {"restitution"};
    case Family::kKdDrag:
      return {"drag"};
    case Family::kSpinRolling:
      return {"spin rolling"};
    case Family::kDepthFrictionExp:
      return {"depth friction"};
    case Family::kRankinePlough:
      return {"ploughing"};
    case Family::kTwo:
      return {"restitution", "spin rolling"};
    case Family::kDepthSpeedDrag:
      return {"drag"};
    case Family::kYieldRestitution:
      return {"restitution"};
    case Family::kSlipSpinFriction:
      return {"slip friction"};
    case Family::kRateThresholdDrag:
      return {"drag"};
    default:
      return {};
  }
}

bool names_family(Family f, const std::string& candidate) {
  const auto expected = expected_families(f);
  for (std::size_t a = 0, b; a <= candidate.size(); a = b + 1) {
    b = candidate.find('+', a);
    if (b == std::string::npos) b = candidate.size();
    const std::string fam = candidate_family(candidate.substr(a, b - a));
    if (std::find(expected.begin(), expected.end(), fam) != expected.end()) return true;
  }
  return false;
}

Rebound collide(const std::array<double, 3>& vin, const Ground& g, const Numerics& num,
                std::vector<TraceSample>* trace, long trace_every, std::vector<PathSample>* path) {
  const double dt = num.dt;
  // The disc starts 0.1 micrometre above the ground with V_in (paper Fig. 14: a positive,
  // almost zero gap).
  double y = kRadius + 1e-7, vx = vin[0], vy = vin[1], w = vin[2];
  double x = 0, th = 0;  // only recorded (a disc on flat ground does not depend on them)
  double fn = 0, ft = 0, mom = 0, h_prev = 0, vn0 = 0, t_touch = 0;
  bool touched = false;
  Rebound out;
  const double s = g.strength;
  const long steps = static_cast<long>(std::ceil(num.max_time / dt));
  for (long i = 0; i < steps; ++i) {
    const double h = kRadius - y;  // overlap with the ground y = 0
    double fx = 0, fy = -kMass * num.gravity, tq = 0;
    if (h > 0) {
      if (!touched) vn0 = -vy, t_touch = i * dt;
      touched = true;
      out.peak_overlap = std::max(out.peak_overlap, h);
      double en2 = g.en2;
      if (has(g, Family::kCrspRestitution)) {
        // CRSP / Pfeiffer & Bowen (1989): R_n -> R_n / (1 + (v_n / v_c)^2); e_n^2 = R_n^2.
        const double r = 1.0 + s * (vn0 / kVc) * (vn0 / kVc);
        en2 /= r * r;
      }
      // Thornton & Ning (1998): constant below the yield speed, e ~ (v_yield / v)^(s/4) above.
      if (has(g, Family::kYieldRestitution) && vn0 > kYieldSpeed)
        en2 *= std::pow(kYieldSpeed / vn0, 0.5 * s);
      // Normal: incremental loading, direct unloading to e_n^2 kn h (paper Eq. 3).
      const double dh = h - h_prev;
      fn = dh >= 0 ? fn + num.kn * dh : std::min(fn, en2 * num.kn * h);
      fn = std::max(fn, 0.0);
      double normal = fn;
      double hidden_n = 0, hidden_t = 0;
      // Katsuragi & Durian (2007): m z'' = m g - k z - (m/d1) z'^2 while penetrating.
      if (has(g, Family::kKdDrag) && vy < 0) hidden_n += s * kDragRef * vy * vy;
      // A drag whose coefficient grows with depth: c_hv h v_y^2 while penetrating.
      if (has(g, Family::kDepthSpeedDrag) && vy < 0) hidden_n += s * kDepthSpeedRef * h * vy * vy;
      // A drag above a penetration rate only: c_rt (|v_y| - v_th)^2 while -v_y > v_th.
      if (has(g, Family::kRateThresholdDrag) && -vy > kRateThreshold)
        hidden_n += s * kRateDragRef * (-vy - kRateThreshold) * (-vy - kRateThreshold);
      normal += hidden_n;
      const double l = kRadius - h;  // centre to the contact point on the ground surface
      const double vt = vx + w * l;  // slip of the contact point
      double mu = g.mu;
      // Depth-hardening friction, quadratic in depth (not the catalog's linear mu (1 + a h)).
      if (has(g, Family::kDepthFrictionExp)) mu *= 1.0 + s * (h / kDepthRef) * (h / kDepthRef);
      // Friction growing with the product of slip and spin (no generated law has a product).
      if (has(g, Family::kSlipSpinFriction)) mu *= 1.0 + s * kSlipSpinRef * std::fabs(vt * w);
      ft = std::clamp(ft - num.kt * vt * dt, -mu * normal, mu * normal);
      double muR = g.muR;
      // Spin-dependent rolling resistance mu_R (1 + c_w |omega|) (no literature form).
      if (has(g, Family::kSpinRolling)) muR *= 1.0 + s * kSpinRef * std::fabs(w);
      mom = std::clamp(mom - num.kr * w * dt, -muR * l * normal, muR * l * normal);
      fx += ft;
      // Rankine passive earth pressure 1/2 K_p gamma h^2 L against the horizontal motion.
      if (has(g, Family::kRankinePlough))
        hidden_t = -(vx > 0 ? 1.0 : vx < 0 ? -1.0 : 0.0) * s * kPloughRef * h * h;
      fx += hidden_t;
      fy += normal;
      tq += l * ft + mom;
      if (trace && i % trace_every == 0) {
        const bool additive = !has(g, Family::kCrspRestitution) &&
                              !has(g, Family::kYieldRestitution) &&
                              !has(g, Family::kDepthFrictionExp) &&
                              !has(g, Family::kSlipSpinFriction) && !has(g, Family::kSpinRolling);
        trace->push_back({i * dt, h, vy, vt, vx, w, dh > 0, normal, ft + hidden_t, l * ft + mom,
                          additive ? hidden_n : NAN, additive ? hidden_t : NAN});
      }
    } else {
      fn = ft = mom = 0;
      // End of contact: out of the ground with the centre rising, so the ballistic clearance
      // of a disc over flat ground is positive from now on.
      if (touched && vy > 0 && h < 0) {
        out.vout = {vx, vy, w};
        out.ok = true;
        out.duration = i * dt - t_touch;
        return out;
      }
    }
    if (path && i % trace_every == 0)
      path->push_back({i * dt, x, y, th, vx, vy, w, fx, fy + kMass * num.gravity, tq});
    h_prev = std::max(h, 0.0);
    // Semi-implicit Euler: velocities first, then the position with the new velocity.
    vx += fx / kMass * dt;
    vy += fy / kMass * dt;
    w += tq / kInertia * dt;
    y += vy * dt;
    x += vx * dt;
    th += w * dt;
  }
  out.vout = {vx, vy, w};
  return out;
}

double shift_in_lab_units(const std::array<double, 3>& mean_shift) {
  double m = 0;
  for (int k = 0; k < 3; ++k) m = std::max(m, std::fabs(mean_shift[k]) / kLabScale[k]);
  return m;
}

namespace {
std::string fmt_ground(const SetOptions& o) {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "Ground per release: en2 U(%.2f,%.2f), mu U(%.2f,%.2f), muR U(%.2f,%.2f).",
                o.scatter_lo[0], o.scatter_hi[0], o.scatter_lo[1], o.scatter_hi[1], o.scatter_lo[2],
                o.scatter_hi[2]);
  return buf;
}
}  // namespace

TruthSet make_set(const SetOptions& o) {
  if (o.n == 0) throw std::invalid_argument("n must be positive");
  if (!(o.strength >= 0)) throw std::invalid_argument("strength must be >= 0");
  if (o.design == Design::kLab && o.lab_vin.size() < 2)
    throw std::invalid_argument("the lab design needs the lab's incident states");
  if (o.design == Design::kGiven && o.given_vin.size() < o.n)
    throw std::invalid_argument("the given design needs n incident states");
  Rng rng(o.seed);
  // Silverman's bandwidth 1.06 sd n^(-1/5) of each V_in component of the lab states.
  std::array<double, 3> bw{};
  if (o.design == Design::kLab) {
    const double n = static_cast<double>(o.lab_vin.size());
    for (int k = 0; k < 3; ++k) {
      double m = 0, q = 0;
      for (const auto& v : o.lab_vin) m += v[k] / n;
      for (const auto& v : o.lab_vin) q += (v[k] - m) * (v[k] - m) / (n - 1);
      bw[k] = 1.06 * std::sqrt(q) * std::pow(n, -0.2);
    }
  }
  TruthSet out;
  out.set.source = "independent_truth";
  std::mt19937_64 track_rng(o.seed ^ kTrackSeedSalt);
  std::normal_distribution<double> track_noise(0.0, 1.0);
  std::vector<std::array<double, 3>> vins, vouts, deltas;
  std::vector<Ground> grounds;
  std::vector<Rebound> nulls;
  nlohmann::json releases = nlohmann::json::array();
  std::array<double, 3> sum{}, sq{};
  std::size_t redrawn = 0;
  while (out.set.size() < o.n) {
    // Draw order per release (fixed: reproducibility): incident state, ground, noise.
    std::array<double, 3> vin;
    if (o.design == Design::kLab) {
      const auto& base = o.lab_vin[std::min(
          o.lab_vin.size() - 1, static_cast<std::size_t>(rng.uniform() * o.lab_vin.size()))];
      for (int k = 0; k < 3; ++k) vin[k] = base[k] + bw[k] * rng.normal();
    } else if (o.design == Design::kGiven) {
      vin = o.given_vin[out.set.size()];
    } else {
      vin = {rng.uniform(1.5, 6.0), rng.uniform(-5.0, -1.0), rng.uniform(-90.0, 0.0)};
    }
    Ground g{rng.uniform(o.scatter_lo[0], o.scatter_hi[0]),
             rng.uniform(o.scatter_lo[1], o.scatter_hi[1]),
             rng.uniform(o.scatter_lo[2], o.scatter_hi[2]), o.family, o.strength};
    std::array<double, 3> nin, nout;
    for (int k = 0; k < 3; ++k) nin[k] = rng.normal();
    for (int k = 0; k < 3; ++k) nout[k] = rng.normal();
    std::array<double, 2> ncontact{};
    if (o.contact_features)
      for (double& x : ncontact) x = rng.normal();
    std::vector<PathSample> path;
    const long every = std::max(1L, std::lround(kTrackInterval_s / o.numerics.dt));
    const Rebound r = collide(vin, g, o.numerics, nullptr, every, o.tracks ? &path : nullptr);
    Impact im;
    for (int k = 0; k < 3; ++k) {
      im.vin[k] = vin[k] + kNoiseIn[k] * nin[k];
      im.vout[k] = r.vout[k] + kNoiseOut[k] * nout[k];
    }
    if (o.contact_features) {
      im.penetration = r.peak_overlap + o.noise_penetration_m * ncontact[0];
      im.contact_duration = r.duration + o.noise_contact_duration_s * ncontact[1];
    }
    // A release the lab could not have recorded (no rebound, not falling, not rising; a
    // non-positive penetration or duration) is drawn again; the count is in the provenance.
    if (!r.ok || vin[1] >= 0 || im.vin[1] >= 0 || im.vout[1] <= 0 ||
        (o.contact_features && (*im.penetration <= 0 || *im.contact_duration <= 0))) {
      ++redrawn;
      continue;
    }
    Ground null = g;
    null.family = Family::kNone;
    const Rebound r0 = collide(vin, null, o.numerics);
    std::array<double, 3> delta;
    for (int k = 0; k < 3; ++k) {
      delta[k] = r.vout[k] - r0.vout[k];
      sum[k] += delta[k];
      sq[k] += delta[k] * delta[k];
    }
    char id[32];
    std::snprintf(id, sizeof id, "%s%03zu", o.id_prefix.c_str(), out.set.size() + 1);
    im.id = id;
    im.shape = "cylinder";
    out.set.impacts.push_back(im);
    if (o.tracks) {
      BlockTrack tr;
      tr.block_mass_kg = kMass;
      for (const PathSample& p : path) {
        for (auto [col, v] : {std::pair{&tr.t, p.t_s},
                              {&tr.x, p.x_m},
                              {&tr.y, p.y_m},
                              {&tr.theta, p.theta_rad},
                              {&tr.vx, p.vx_mps},
                              {&tr.vy, p.vy_mps},
                              {&tr.w, p.w_radps}})
          col->push_back(v);
        tr.fcx.push_back(p.fx_N + o.track_force_noise_N * track_noise(track_rng));
        tr.fcy.push_back(p.fy_N + o.track_force_noise_N * track_noise(track_rng));
      }
      tr.pad();
      out.tracks.push_back(std::move(tr));
    }
    vins.push_back(vin);
    vouts.push_back(r.vout);
    deltas.push_back(delta);
    grounds.push_back(null);
    nulls.push_back(r0);
    releases.push_back({{"id", im.id},
                        {"vin_true", vin},
                        {"vout_true", r.vout},
                        {"vout_without_effect", r0.vout},
                        {"en2", g.en2},
                        {"mu", g.mu},
                        {"muR", g.muR},
                        {"peak_overlap_m", r.peak_overlap},
                        {"contact_duration_s", r.duration}});
  }
  const double n = static_cast<double>(o.n);
  for (int k = 0; k < 3; ++k) {
    out.mean_shift[k] = sum[k] / n;
    out.rms_shift[k] = std::sqrt(sq[k] / n);
  }
  // What recalibrating the paper's constants cannot absorb: the best common change (d_en2,
  // d_mu, d_muR) of every release's ground, without the effect, in lab-scale least squares.
  std::array<double, 3> delta{};
  if (o.refit && o.family != Family::kNone && o.strength > 0) {
    auto misfit = [&](const std::array<double, 3>& d, std::array<double, 3>* rms) {
      std::array<double, 3> s2{};
      for (std::size_t i = 0; i < grounds.size(); ++i) {
        Ground g = grounds[i];
        g.en2 = std::clamp(g.en2 + d[0], 1e-4, 1.0);
        g.mu = std::max(g.mu + d[1], 0.0);
        g.muR = std::max(g.muR + d[2], 0.0);
        const Rebound r = collide(vins[i], g, o.numerics);
        for (int k = 0; k < 3; ++k) s2[k] += (r.vout[k] - vouts[i][k]) * (r.vout[k] - vouts[i][k]);
      }
      double f = 0;
      for (int k = 0; k < 3; ++k) {
        if (rms) (*rms)[k] = std::sqrt(s2[k] / n);
        f += s2[k] / (kLabScale[k] * kLabScale[k]);
      }
      return f;
    };
    const auto best = nelder_mead(
        [&](const std::vector<double>& x) {
          return misfit({x[0], x[1], x[2]}, nullptr);
        },
        {0.0, 0.0, 0.0}, {0.02, 0.05, 0.02}, 120);
    delta = {best[0], best[1], best[2]};
    misfit(delta, &out.residual_rms);
  }
  // The oracle (header, [1]-[2]); also at strength 0, where delta_i = 0 exactly gives z = 0.
  nlohmann::json oracle;
  if (o.refit) {
    if (o.oracle_family_size == 0) throw std::invalid_argument("oracle family size must be >= 1");
    if (o.family != Family::kNone)
      out.oracle_z = oracle_z(vins, grounds, nulls, deltas, o.numerics, o.scatter_lo, o.scatter_hi);
    const double family_alpha = kOracleAlpha / static_cast<double>(o.oracle_family_size);
    oracle = {
        {"z", out.oracle_z},
        {"power_single", oracle_power(out.oracle_z, kOracleAlpha)},
        {"power_family", oracle_power(out.oracle_z, family_alpha)},
        {"alpha_single", kOracleAlpha},
        {"alpha_family", family_alpha},
        {"family_size", o.oracle_family_size},
        {"assumptions",
         "power Phi(z - z_{1-alpha}) of the one-sided Neyman-Pearson test of the known effect "
         "shape after re-estimating (e_n^2, mu, mu_R); Gaussian linearised errors: V_out noise + "
         "ground scatter (uniform variances) and V_in noise propagated by central-difference "
         "Jacobians on the law without the effect; exact noise and scatter covariances known; "
         "in that model no test of this alternative has more power; on this nonlinear "
         "simulator the ceiling is optimistic (tests/detection/truth_sim.hpp)"}};
  }
  const std::string design = o.design == Design::kLab    ? "lab"
                             : o.design == Design::kWide ? "wide"
                                                         : "given";
  out.set.comments = {
      "Ricochet impact set v1. Independent truth (tests/detection/truth_sim.hpp): a second "
      "implementation of the paper's law, semi-implicit Euler, dt 2e-6 s, kn = kt = 3e7 N/m, kr = "
      "5e7 N m/rad.",
      std::to_string(o.n) + " cylinder releases, seed " + std::to_string(o.seed) + ", design " +
          design +
          ". Noise (1 sd): V_in 0.05 m/s, 0.05 m/s, 1.4 rad/s; V_out 0.05 m/s, 0.03 m/s, 2 "
          "rad/s. " +
          fmt_ground(o)};
  const Reference ref = reference(o.family);
  const Numerics& num = o.numerics;
  nlohmann::json design_json = {{"name", design}};
  if (o.design == Design::kLab) {
    design_json["description"] =
        "smoothed bootstrap of the lab's incident states: a lab state at random plus a Gaussian "
        "kernel of Silverman's bandwidth per component";
    design_json["lab_source"] = o.lab_source;
    design_json["lab_states"] = o.lab_vin.size();
    design_json["bandwidth"] = bw;
  } else {
    design_json["description"] =
        "uniform V_in^x in [1.5, 6] m/s, V_in^y in [-5, -1] m/s, omega_in in [-90, 0] rad/s";
  }
  out.truth = {
      {"generator", "independent_truth (tests/detection/truth_sim.hpp)"},
      {"family", family_name(o.family)},
      {"strength", o.strength},
      {"reference_strength", reference_strength(o.family)},
      {"reference",
       {{"parameter", ref.parameter},
        {"value", ref.value},
        {"unit", ref.unit},
        {"literature", ref.literature}}},
      {"expected_families", expected_families(o.family)},
      {"n", o.n},
      {"seed", o.seed},
      {"rng", "std::mt19937_64; uniform = top 53 bits; normal = Box-Muller"},
      {"design", design},
      {"design_detail", design_json},
      {"redrawn", redrawn},
      {"mean_shift", out.mean_shift},
      {"rms_shift", out.rms_shift},
      {"shift_in_lab_units", shift_in_lab_units(out.mean_shift)},
      {"residual_rms_after_refit", out.residual_rms},
      {"refit_delta", {{"en2", delta[0]}, {"mu", delta[1]}, {"muR", delta[2]}}},
      {"lab_scale", kLabScale},
      {"block",
       {{"shape", "cylinder"},
        {"R_m", kRadius},
        {"m_kg", kMass},
        {"I_kgm2", kInertia},
        {"L_m", kLength}}},
      {"numerics",
       {{"integrator", "semi-implicit Euler"},
        {"dt_s", num.dt},
        {"kn_N_per_m", num.kn},
        {"kt_N_per_m", num.kt},
        {"kr_Nm_per_rad", num.kr},
        {"gravity_m_per_s2", num.gravity},
        {"lever_arm", "R - h"},
        {"end_of_contact", "out of the ground with the centre rising"}}},
      {"scatter",
       {{"en2", {o.scatter_lo[0], o.scatter_hi[0]}},
        {"mu", {o.scatter_lo[1], o.scatter_hi[1]}},
        {"muR", {o.scatter_lo[2], o.scatter_hi[2]}},
        {"distribution", "uniform, drawn per release"}}},
      {"noise", {{"vin", kNoiseIn}, {"vout", kNoiseOut}, {"distribution", "Gaussian, 1 sd"}}},
      {"observables",
       o.contact_features
           ? std::vector<std::string>{"vin_x", "vin_y", "win", "vout_x", "vout_y", "wout",
                                      "penetration", "contact_duration"}
           : std::vector<std::string>{"vin_x", "vin_y", "win", "vout_x", "vout_y", "wout"}},
      {"releases", releases}};
  if (!oracle.is_null()) out.truth["oracle"] = oracle;
  if (o.contact_features) {
    out.truth["noise"]["penetration_m"] = o.noise_penetration_m;
    out.truth["noise"]["contact_duration_s"] = o.noise_contact_duration_s;
  }
  return out;
}

double lab_scale_strength(SetOptions o) {
  if (o.family == Family::kNone) throw std::invalid_argument("the null family has no strength");
  o.refit = false;
  auto shift = [&](double s) {
    o.strength = s;
    return shift_in_lab_units(make_set(o).mean_shift);
  };
  double lo = 1.0, hi = 1.0;
  if (shift(1.0) >= 1.0) {
    do {
      hi = lo, lo /= 4.0;
    } while (shift(lo) >= 1.0 && lo > 1e-6);
  } else {
    do {
      lo = hi, hi *= 4.0;
      if (hi > 1e6) throw std::runtime_error("no strength up to 1e6 reaches the lab scale");
    } while (shift(hi) < 1.0);
  }
  while (hi / lo > 1.001) {
    const double mid = std::sqrt(lo * hi);
    (shift(mid) < 1.0 ? lo : hi) = mid;
  }
  return hi;
}

std::vector<std::array<double, 3>> lab_cylinder_states(const std::string& path) {
  std::vector<std::array<double, 3>> v;
  for (const auto& im : read_impact_set(path).impacts)
    if (im.shape == "cylinder") v.push_back(im.vin);
  return v;
}

}  // namespace ricochet::truth
