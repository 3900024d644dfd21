#include "truth_sim.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace ricochet::truth {
namespace {

// The lab cylinder (paper Fig. 4 caption; notes).
constexpr double kR = 0.08, kM = 13.9, kI = 0.0445, kG = 9.81;
// This implementation's own numerics (file comment).
constexpr double kDt = 2e-6, kKn = 3e7, kKt = 3e7, kKr = 5e7, kMaxTime = 0.2;

const std::vector<std::string> kNames = {"none",         "crsp_restitution",   "kd_drag",
                                         "spin_rolling", "depth_friction_exp", "rankine_plough",
                                         "two"};

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
  double normal() {  // Box-Muller
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
};

}  // namespace

const std::vector<std::string>& family_names() {
  return kNames;
}

Family family_from_name(const std::string& name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return static_cast<Family>(i);
  std::string list;
  for (const auto& n : kNames) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown family '" + name + "'; accepted: " + list);
}

std::string reference_strength(Family f) {
  switch (f) {
    case Family::kCrspRestitution:
      return "v_c = 9.144 m/s (CRSP, Pfeiffer & Bowen 1989)";
    case Family::kKdDrag:
      return "m/d1 = 40 kg/m (Katsuragi & Durian 2007 scaled to the lab cylinder, notes)";
    case Family::kSpinRolling:
      return "c_w = 0.01 s/rad (no literature value: +65 % of mu_R at 65 rad/s)";
    case Family::kDepthFrictionExp:
      return "mu (1 + (h / 3 mm)^2) (no literature value; 3 mm = the overlap scale)";
    case Family::kRankinePlough:
      return "1/2 K_p gamma L = 8.4e3 N/m^2 x h^2 (Rankine, K_p 3.7, gamma 15.7 kN/m^3, L 0.29 m)";
    case Family::kTwo:
      return "crsp_restitution and spin_rolling at the same strength";
    default:
      return "none";
  }
}

bool names_family(Family f, const std::string& candidate) {
  for (std::size_t a = 0, b; a <= candidate.size(); a = b + 1) {
    b = candidate.find('+', a);
    if (b == std::string::npos) b = candidate.size();
    const std::string e = candidate.substr(a, b - a);
    auto starts = [&](const char* p) { return e.rfind(p, 0) == 0; };
    const bool restitution = e == "rate_restitution" || starts("en2_");
    const bool spin = starts("muR_spin_");
    switch (f) {
      case Family::kCrspRestitution:
        if (restitution) return true;
        break;
      case Family::kKdDrag:
        if (e == "inertial_drag") return true;
        break;
      case Family::kSpinRolling:
        if (spin) return true;
        break;
      case Family::kDepthFrictionExp:
        if (e == "depth_friction" || starts("mu_penetration_")) return true;
        break;
      case Family::kRankinePlough:
        if (e == "ploughing") return true;
        break;
      case Family::kTwo:
        if (restitution || spin) return true;
        break;
      default:
        break;
    }
  }
  return false;
}

Rebound collide(const std::array<double, 3>& vin, const Ground& g) {
  double y = kR + 1e-7, vx = vin[0], vy = vin[1], w = vin[2];
  double fn = 0, ft = 0, mom = 0, h_prev = 0, vn0 = 0;
  bool touched = false;
  const double s = g.strength;
  for (double t = 0; t < kMaxTime; t += kDt) {
    const double h = kR - y;
    double fx = 0, fy = -kM * kG, tq = 0;
    if (h > 0) {
      if (!touched) vn0 = -vy;
      touched = true;
      double en2 = g.en2;
      if (has(g, Family::kCrspRestitution)) {
        const double r = 1.0 + s * (vn0 / 9.144) * (vn0 / 9.144);
        en2 /= r * r;
      }
      const double dh = h - h_prev;
      fn = dh >= 0 ? fn + kKn * dh : std::min(fn, en2 * kKn * h);
      fn = std::max(fn, 0.0);
      double fnormal = fn;
      if (has(g, Family::kKdDrag) && vy < 0) fnormal += s * 40.0 * vy * vy;
      const double l = kR - h;
      const double vt = vx + w * l;
      double mu = g.mu;
      if (has(g, Family::kDepthFrictionExp)) mu *= 1.0 + s * (h / 3e-3) * (h / 3e-3);
      ft = std::clamp(ft - kKt * vt * kDt, -mu * fnormal, mu * fnormal);
      double muR = g.muR;
      if (has(g, Family::kSpinRolling)) muR *= 1.0 + s * 0.01 * std::fabs(w);
      mom = std::clamp(mom - kKr * w * kDt, -muR * l * fnormal, muR * l * fnormal);
      fx += ft;
      if (has(g, Family::kRankinePlough))
        fx -= (vx > 0 ? 1.0 : vx < 0 ? -1.0 : 0.0) * s * 0.5 * 3.7 * 15.7e3 * h * h * 0.29;
      fy += fnormal;
      tq += l * ft + mom;
    } else {
      fn = ft = mom = 0;
      if (touched && vy > 0) return {{vx, vy, w}, true};
    }
    h_prev = std::max(h, 0.0);
    // Semi-implicit Euler: velocities first, then the position with the new velocity.
    vx += fx / kM * kDt;
    vy += fy / kM * kDt;
    w += tq / kI * kDt;
    y += vy * kDt;
  }
  return {{vx, vy, w}, false};
}

TruthSet make_set(const SetOptions& o) {
  if (o.n == 0) throw std::invalid_argument("n must be positive");
  if (o.design == Design::kLab && o.lab_vin.size() < 2)
    throw std::invalid_argument("the lab design needs the lab's incident states");
  Rng rng(o.seed);
  // Silverman bandwidth of each V_in component of the lab states.
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
  const std::array<double, 3> sin{0.05, 0.05, 1.4}, sout{0.05, 0.03, 2.0};
  TruthSet out;
  out.set.source = "independent_truth";
  nlohmann::json releases = nlohmann::json::array();
  std::array<double, 3> sum{}, sq{};
  std::size_t redrawn = 0;
  while (out.set.size() < o.n) {
    std::array<double, 3> vin;
    if (o.design == Design::kLab) {
      const auto& base = o.lab_vin[std::min(
          o.lab_vin.size() - 1, static_cast<std::size_t>(rng.uniform() * o.lab_vin.size()))];
      for (int k = 0; k < 3; ++k) vin[k] = base[k] + bw[k] * rng.normal();
    } else {
      vin = {rng.uniform(1.5, 6.0), rng.uniform(-5.0, -1.0), rng.uniform(-90.0, 0.0)};
    }
    Ground g{rng.uniform(0.12, 0.20), rng.uniform(0.25, 0.45), rng.uniform(0.12, 0.20), o.family,
             o.strength};
    std::array<double, 3> nin, nout;
    for (int k = 0; k < 3; ++k) nin[k] = rng.normal();
    for (int k = 0; k < 3; ++k) nout[k] = rng.normal();
    const Rebound r = collide(vin, g);
    Impact im;
    for (int k = 0; k < 3; ++k) {
      im.vin[k] = vin[k] + sin[k] * nin[k];
      im.vout[k] = r.vout[k] + sout[k] * nout[k];
    }
    if (!r.ok || vin[1] >= 0 || im.vin[1] >= 0 || im.vout[1] <= 0) {
      ++redrawn;
      continue;
    }
    Ground null = g;
    null.family = Family::kNone;
    const Rebound r0 = collide(vin, null);
    for (int k = 0; k < 3; ++k) {
      const double d = r.vout[k] - r0.vout[k];
      sum[k] += d;
      sq[k] += d * d;
    }
    char id[32];
    std::snprintf(id, sizeof id, "T%03zu", out.set.size() + 1);
    im.id = id;
    im.shape = "cylinder";
    out.set.impacts.push_back(im);
    releases.push_back({{"id", im.id},
                        {"vin_true", vin},
                        {"vout_true", r.vout},
                        {"vout_without_effect", r0.vout},
                        {"en2", g.en2},
                        {"mu", g.mu},
                        {"muR", g.muR}});
  }
  const double n = static_cast<double>(o.n);
  for (int k = 0; k < 3; ++k) {
    out.mean_shift[k] = sum[k] / n;
    out.rms_shift[k] = std::sqrt(sq[k] / n);
  }
  const std::string fam = kNames[static_cast<int>(o.family)];
  out.set.comments = {
      "Ricochet impact set v1. Independent truth (tests/detection/truth_sim.hpp): a second "
      "implementation of the paper's law, semi-implicit Euler, dt 2e-6 s, kn = kt = 3e7 N/m, kr = "
      "5e7 N m/rad.",
      std::to_string(o.n) + " cylinder releases, seed " + std::to_string(o.seed) + ", design " +
          (o.design == Design::kLab ? "lab" : "wide") +
          ". Noise (1 sd): V_in 0.05 m/s, 0.05 m/s, 1.4 rad/s; V_out 0.05 m/s, 0.03 m/s, 2 rad/s. "
          "Ground per release: en2 U(0.12,0.20), mu U(0.25,0.45), muR U(0.12,0.20)."};
  out.truth = {{"family", fam},
               {"strength", o.strength},
               {"reference_strength", reference_strength(o.family)},
               {"n", o.n},
               {"seed", o.seed},
               {"design", o.design == Design::kLab ? "lab" : "wide"},
               {"redrawn", redrawn},
               {"mean_shift", out.mean_shift},
               {"rms_shift", out.rms_shift},
               {"numerics",
                {{"integrator", "semi-implicit Euler"},
                 {"dt_s", kDt},
                 {"kn", kKn},
                 {"kt", kKt},
                 {"kr", kKr}}},
               {"noise", {{"vin", sin}, {"vout", sout}}},
               {"releases", releases}};
  return out;
}

}  // namespace ricochet::truth
