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

namespace {

// One release's contact samples on the wide design and the force noise drawn for each (normal,
// tangential), in the order traced_set has always drawn them: the set's releases, paths and noise
// for a seed, shared by the set and its oracle.
struct NoisySample {
  TraceSample t;
  double noise_n_N = 0, noise_t_N = 0;
};
std::vector<std::vector<NoisySample>> traced_releases(Family f, double strength,
                                                      std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> vx(1.5, 6.0), vy(-5.0, -1.0), w(-90.0, 0.0);
  std::normal_distribution<double> noise(0.0, kForceNoiseN);
  const Ground g{0.16, 0.35, 0.16, f, strength};
  std::vector<std::vector<NoisySample>> out;
  for (int i = 0; i < 30; ++i) {
    const std::array<double, 3> vin = {vx(rng), vy(rng), w(rng)};
    std::vector<TraceSample> trace;
    (void)collide(vin, g, Numerics{}, &trace, 100);
    std::vector<NoisySample> release;
    for (const TraceSample& t : trace) {
      const double n = noise(rng);
      release.push_back({t, n, noise(rng)});
    }
    out.push_back(std::move(release));
  }
  return out;
}

}  // namespace

std::vector<ReleaseResidual> traced_set(Family f, double strength, std::uint64_t seed) {
  std::vector<ReleaseResidual> out;
  for (const auto& release : traced_releases(f, strength, seed)) {
    ReleaseResidual r;
    for (const NoisySample& x : release) {
      ContactSample s;
      s.h_m = x.t.h_m;
      s.vn_mps = x.t.vn_mps;
      s.vt_mps = x.t.vt_mps;
      s.vx_mps = x.t.vx_mps;
      s.omega_radps = x.t.omega_radps;
      s.loading = x.t.loading;
      r.samples.push_back(s);
      r.residual.push_back({x.t.hidden_fn_N + x.noise_n_N, x.t.hidden_ft_N + x.noise_t_N, NAN});
    }
    out.push_back(std::move(r));
  }
  return out;
}

double oracle_z(Family f, double strength, std::uint64_t seed) {
  std::vector<double> g, r;
  for (const auto& release : traced_releases(f, strength, seed))
    for (const NoisySample& x : release) {
      g.push_back(x.t.hidden_fn_N / strength);
      r.push_back(x.t.hidden_fn_N + x.noise_n_N);
      g.push_back(x.t.hidden_ft_N / strength);
      r.push_back(x.t.hidden_ft_N + x.noise_t_N);
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

bool finds(const std::vector<diagnosis::ComponentLaw>& laws, const std::set<std::string>& terms) {
  const auto selected = selected_terms(laws);
  for (const auto& name : terms)
    if (selected.count(name)) return true;
  return false;
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
  for (std::uint64_t seed = first; seed < first + n; ++seed)
    found += finds(discover(make, f, strength, seed, log), terms);
  return found;
}

}  // namespace ricochet::truth
