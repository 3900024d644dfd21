// The force-residual data sets of the independent simulator (force_sets.hpp).
#include "force_sets.hpp"

#include <cmath>
#include <random>

#include "diagnosis/force_residual.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"

namespace ricochet::truth {

using diagnosis::ContactSample;
using diagnosis::ReleaseResidual;

std::vector<ReleaseResidual> traced_set(Family f, double strength, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> vx(1.5, 6.0), vy(-5.0, -1.0), w(-90.0, 0.0);
  std::normal_distribution<double> noise(0.0, kForceNoiseN);
  std::vector<ReleaseResidual> out;
  for (int i = 0; i < 30; ++i) {
    const std::array<double, 3> vin = {vx(rng), vy(rng), w(rng)};
    std::vector<TraceSample> trace;
    const Ground g{0.16, 0.35, 0.16, f, strength};
    (void)collide(vin, g, Numerics{}, &trace, 100);
    ReleaseResidual r;
    for (const TraceSample& t : trace) {
      ContactSample s;
      s.h_m = t.h_m;
      s.vn_mps = t.vn_mps;
      s.vt_mps = t.vt_mps;
      s.vx_mps = t.vx_mps;
      s.omega_radps = t.omega_radps;
      s.loading = t.loading;
      r.samples.push_back(s);
      r.residual.push_back({t.hidden_fn_N + noise(rng), t.hidden_ft_N + noise(rng), NAN});
    }
    out.push_back(std::move(r));
  }
  return out;
}

// The same draws as traced_set, in the same order, so that the oracle sees that set's noise.
double oracle_z(Family f, double strength, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> vx(1.5, 6.0), vy(-5.0, -1.0), w(-90.0, 0.0);
  std::normal_distribution<double> noise(0.0, kForceNoiseN);
  std::vector<double> g, r;
  for (int i = 0; i < 30; ++i) {
    const std::array<double, 3> vin = {vx(rng), vy(rng), w(rng)};
    std::vector<TraceSample> trace;
    const Ground ground{0.16, 0.35, 0.16, f, strength};
    (void)collide(vin, ground, Numerics{}, &trace, 100);
    for (const TraceSample& t : trace) {
      g.push_back(t.hidden_fn_N / strength);
      r.push_back(t.hidden_fn_N + noise(rng));
      g.push_back(t.hidden_ft_N / strength);
      r.push_back(t.hidden_ft_N + noise(rng));
    }
  }
  double gg = 0, gr = 0;
  for (std::size_t k = 0; k < g.size(); ++k) {
    gg += g[k] * g[k];
    gr += g[k] * r[k];
  }
  if (!(gg > 0) || g.size() < 2) return 0;
  const double b = gr / gg;
  double ss = 0;
  for (std::size_t k = 0; k < g.size(); ++k) ss += (r[k] - b * g[k]) * (r[k] - b * g[k]);
  const double s = std::sqrt(ss / static_cast<double>(g.size() - 1));
  return b / (s / std::sqrt(gg));
}

// The residual is the hidden force plus what the two implementations do differently (truth_sim.hpp:
// integrator, step, the lever R - h against the engine's R - h / 2); the path evaluation
// sub-steps between the records at the engine's dt.
std::vector<ReleaseResidual> traced_set_through_law(Family f, double strength, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> vx(1.5, 6.0), vy(-5.0, -1.0), w(-90.0, 0.0);
  std::normal_distribution<double> noise(0.0, kForceNoiseN);
  const Ground g{0.16, 0.35, 0.16, f, strength};
  const Numerics num{};
  Model law = Model::paper();
  law.set("kn", num.kn);
  law.set("kt", num.kt);
  law.set("kr", num.kr);
  law.set("en2", g.en2);
  law.set("mu", g.mu);
  law.set("muR", g.muR);
  const Shape disc = Shape::cylinder();
  std::vector<ReleaseResidual> out;
  for (int i = 0; i < 30; ++i) {
    const std::array<double, 3> vin = {vx(rng), vy(rng), w(rng)};
    std::vector<PathSample> path;
    (void)collide(vin, g, num, nullptr, 100, &path);
    diagnosis::MeasuredHistory h;
    for (const PathSample& p : path) {
      h.path.push_back({p.t_s, p.x_m, p.y_m, p.theta_rad, p.vx_mps, p.vy_mps, p.w_radps});
      h.fx_N.push_back(p.fx_N + noise(rng));
      h.fy_N.push_back(p.fy_N + noise(rng));
      h.torque_Nm.push_back(NAN);
    }
    out.push_back(diagnosis::force_residual(h, law, disc));
  }
  return out;
}

std::set<std::string> selected_terms(const std::vector<diagnosis::ComponentLaw>& laws) {
  std::set<std::string> s;
  for (const auto& law : laws)
    for (const auto& t : law.terms)
      if (t.selected) s.insert(std::string(t.term->name));
  return s;
}

std::vector<diagnosis::ComponentLaw> discover(const SetMaker& make, Family f, double strength,
                                              std::uint64_t seed, std::string* log) {
  stats::SparseOptions o;
  o.seed = seed;
  o.bootstrap = 0;
  auto laws = diagnosis::discover_force_law(make(f, strength, seed), o);
  if (log)
    for (const auto& law : laws)
      *log += "seed " + std::to_string(seed) + " " +
              std::string(diagnosis::component_name(law.component)) + ": " + law.text + "\n";
  return laws;
}

std::size_t sets_finding(const SetMaker& make, Family f, double strength,
                         const std::set<std::string>& terms, std::uint64_t first, std::size_t n,
                         std::string* log) {
  std::size_t found = 0;
  for (std::uint64_t seed = first; seed < first + n; ++seed) {
    const auto selected = selected_terms(discover(make, f, strength, seed, log));
    bool hit = false;
    for (const auto& name : terms) hit = hit || selected.count(name);
    found += hit;
  }
  return found;
}

}  // namespace ricochet::truth
