// `independent_truth`: writes one impact set made by the independent simulator (truth_sim.hpp)
// and its provenance JSON, or (--calibrate-shift) finds the strength at which the effect's mean
// V_out shift reaches the lab's measurement scale (paper Table 1: 0.1 m/s, 0.1 m/s, 3.4 rad/s).
//
//   independent_truth --family F --strength S --n 40 --design lab|wide --seed K
//                     --out set.csv [--truth truth.json] [--lab data/lab/cylinders.csv]
//   independent_truth --family F --calibrate-shift [--n 40 --seed K]
// Exit codes: 0 ok, 1 runtime failure, 2 bad option (the message names it and its range).
#include <CLI/CLI.hpp>
#include <cmath>
#include <fstream>
#include <iostream>

#include "truth_sim.hpp"

using namespace ricochet;

namespace {

// The largest |mean V_out shift| over components in units of the lab's Table 1 scale.
double shift_in_lab_units(const truth::TruthSet& t) {
  const double scale[3] = {0.1, 0.1, 3.4};
  double m = 0;
  for (int k = 0; k < 3; ++k) m = std::max(m, std::fabs(t.mean_shift[k]) / scale[k]);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Impact sets from an independent simulator with hidden physics"};
  std::string family = "none", design = "lab", out, truth_path, lab;
  double strength = 1.0;
  std::size_t n = 40;
  std::uint64_t seed = 1;
  bool calibrate = false;
  app.add_option("--family", family,
                 "none, crsp_restitution, kd_drag, spin_rolling, "
                 "depth_friction_exp, rankine_plough, two")
      ->capture_default_str();
  app.add_option("--strength", strength, "Multiplier of the family's reference strength, >= 0")
      ->capture_default_str();
  app.add_option("--n", n, "Releases, in [4, 10000]")->capture_default_str();
  app.add_option("--design", design, "lab or wide")->capture_default_str();
  app.add_option("--seed", seed, "Seed of every random draw")->capture_default_str();
  app.add_option("--out", out, "Impact set to write (.csv or .h5)");
  app.add_option("--truth", truth_path, "Provenance JSON (the truth; never read by diagnose)");
  app.add_option("--lab", lab, "Lab cylinders whose incident states the lab design resamples")
      ->capture_default_str();
  app.add_flag("--calibrate-shift", calibrate,
               "Print the strength whose mean V_out shift reaches the lab scale");
  lab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv";
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  auto bad = [](const std::string& what) {
    std::cerr << "independent_truth: " << what << "\n";
    return 2;
  };
  truth::SetOptions o;
  try {
    o.family = truth::family_from_name(family);
  } catch (const std::exception& e) {
    return bad(std::string("--family: ") + e.what());
  }
  if (!(strength >= 0 && strength < 1e6)) return bad("--strength must lie in [0, 1e6)");
  if (n < 4 || n > 10000) return bad("--n must lie in [4, 10000]");
  if (design != "lab" && design != "wide") return bad("--design: use lab or wide");
  if (!calibrate && out.empty()) return bad("--out is required (or --calibrate-shift)");
  o.strength = strength;
  o.n = n;
  o.seed = seed;
  o.design = design == "lab" ? truth::Design::kLab : truth::Design::kWide;
  try {
    for (const auto& im : read_impact_set(lab).impacts) o.lab_vin.push_back(im.vin);
    if (calibrate) {
      // Geometric bisection on the strength: the shift grows monotonically with it.
      double lo = 0.0, hi = 1.0;
      auto shift = [&](double s) {
        o.strength = s;
        return shift_in_lab_units(truth::make_set(o));
      };
      while (shift(hi) < 1.0 && hi < 1e5) lo = hi, hi *= 4.0;
      for (int it = 0; it < 30; ++it) {
        const double mid = lo > 0 ? std::sqrt(lo * hi) : 0.5 * hi;
        (shift(mid) < 1.0 ? lo : hi) = mid;
      }
      std::cout << hi << "\n";
      return 0;
    }
    const truth::TruthSet t = truth::make_set(o);
    write_impact_set(t.set, out);
    if (!truth_path.empty()) {
      nlohmann::json j = t.truth;
      j["shift_in_lab_units"] = shift_in_lab_units(t);
      std::ofstream(truth_path) << j.dump(1) << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "independent_truth: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
