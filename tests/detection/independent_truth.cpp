// `independent_truth`: writes one impact set made by the independent simulator (truth_sim.hpp)
// and its provenance JSON (every setting, the per-release truth, the effect's size in physical
// units), or (--calibrate-shift) prints the strength at which the effect's mean V_out shift
// reaches the lab's measurement scale (paper Table 1: 0.1 m/s, 0.1 m/s, 3.4 rad/s).
//
//   independent_truth --family F --strength S --n 40 --design lab|wide --seed K
//                     --out set.csv [--truth truth.json] [--lab data/lab/cylinders.csv]
//   independent_truth --family F --calibrate-shift [--design lab --n 40 --seed 1]
//   independent_truth --family F --strength S --oracle [--family-size 45] [--design, --n, --seed]
// --contact-features also writes penetration and contact duration (noise 0.5 mm, 1 ms).
// --tracks (.h5 only) also writes each release's tracked history to /dem/tracks/ID.
// --video DIR also writes each release as a camera would film it, DIR/ID.csv (truth_video.hpp;
// --video-fps, --video-noise-m), for `ricochet reconstruct --track-forces`.
// --oracle prints the oracle's z and powers (truth_sim.hpp, "The oracle's ceiling") as one JSON
// line, and writes the set only when --out is given.
// The provenance defaults to the set's path with .truth.json instead of its extension.
// Exit codes: 0 ok, 1 runtime failure, 2 bad option (the message names it and its range).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "truth_sim.hpp"
#include "truth_video.hpp"

using namespace ricochet;

int main(int argc, char** argv) {
  CLI::App app{
      "Impact sets of the lab cylinder from an independent simulator with hidden physics "
      "(docs/detection-benchmark.md)"};
  std::string family = "none", design = "lab", out, truth_path, lab;
  double strength = 1.0;
  long long n = 40;
  std::uint64_t seed = 1;
  bool calibrate = false, no_refit = false, oracle = false, engine_numerics = false;
  bool contact_features = false, tracks = false;
  std::string video_dir;
  truth::VideoOptions video;
  long long family_size = static_cast<long long>(truth::kOracleFamilySize);
  lab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv";
  app.add_option("--family", family,
                 "none, crsp_restitution, kd_drag, spin_rolling, depth_friction_exp, "
                 "rankine_plough, two, depth_speed_drag, yield_restitution, slip_spin_friction")
      ->capture_default_str();
  app.add_option("--strength", strength,
                 "Multiplier of the family's reference strength, in [0, 1e6] (1 = literature "
                 "where there is a value)")
      ->capture_default_str();
  app.add_option("--n", n, "Releases, in [4, 10000]")->capture_default_str();
  app.add_option("--design", design,
                 "lab (the lab's incident states, smoothed bootstrap) or wide (V_in^x 1.5-6 m/s, "
                 "V_in^y -5 to -1 m/s, omega_in -90 to 0 rad/s)")
      ->capture_default_str();
  std::string states, id_prefix = "T", scatter = "narrow";
  app.add_option("--scatter", scatter,
                 "Ground scatter per release: narrow (e_n^2 U(0.12, 0.20), mu U(0.25, 0.45), mu_R "
                 "U(0.12, 0.20)) or lab (the lab's own spread: e_n^2 U(0.08, 0.24), mu_R U(0.02, "
                 "0.62))")
      ->capture_default_str();
  app.add_option("--states", states,
                 "Incident states to throw (a plan of `ricochet design`, or any impact set): the "
                 "given design, one release per row in order; --n is their number");
  app.add_option("--id-prefix", id_prefix, "Prefix of the releases' ids (T001, ...)")
      ->capture_default_str();
  app.add_option("--seed", seed, "Seed of every random draw, in [0, 2^64)")->capture_default_str();
  app.add_option("--out", out, "Impact set to write (.csv or .h5)");
  app.add_option("--truth", truth_path,
                 "Provenance JSON (the truth; never given to diagnose); default: next to --out");
  app.add_option("--lab", lab, "Lab cylinders whose incident states the lab design resamples")
      ->capture_default_str();
  app.add_flag("--tracks", tracks,
               "Also write each release's tracked history to /dem/tracks/ID of the .h5 --out "
               "(a record every 0.2 ms, contact force with 50 N noise; truth_sim.hpp)");
  app.add_option("--video", video_dir,
                 "Also film each release: DIR/ID.csv, the centre and an eccentric mark (0.05 m) "
                 "pointed with Gaussian noise, 30 ms of flight on each side (truth_video.hpp)");
  app.add_option("--video-fps", video.fps, "Frames per second of --video, in [50, 1e5]")
      ->capture_default_str();
  app.add_option("--video-noise-m", video.noise_m,
                 "Pointing noise of --video, sd of each coordinate [m], in [0, 0.05]")
      ->capture_default_str();
  app.add_flag("--contact-features", contact_features,
               "Also write penetration and contact_duration (Gaussian noise 0.5 mm, 1 ms)");
  app.add_flag("--calibrate-shift", calibrate,
               "Print the strength whose mean V_out shift reaches the lab scale (for --design, "
               "--n, --seed) and exit");
  app.add_flag(
      "--engine-numerics", engine_numerics,
      "Use the engine's step and stiffnesses (dt 1e-5 s, kn = kt = 1e7 N/m, kr = 1e8 N m/rad) "
      "instead of this code's: the set then differs from the engine's law only in the "
      "integrator, lever arm and end of contact (a check of what the null sets' false "
      "alarms see)");
  app.add_flag("--no-refit", no_refit,
               "Skip the effect size after recalibrating the paper's constants (faster)");
  app.add_flag("--oracle", oracle,
               "Print the oracle's z and its powers (one hypothesis, Bonferroni family) as JSON");
  app.add_option("--family-size", family_size,
                 "Bonferroni family size of the oracle's family power, in [1, 100000]")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
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
  if (!(strength >= 0 && strength <= 1e6)) {
    char v[32];
    std::snprintf(v, sizeof v, "%g", strength);
    return bad(std::string("--strength ") + v + " is outside [0, 1e6]");
  }
  if (n < 4 || n > 10000) return bad("--n " + std::to_string(n) + " is outside [4, 10000]");
  if (design != "lab" && design != "wide") return bad("--design '" + design + "': use lab or wide");
  if (!calibrate && !oracle && out.empty())
    return bad("--out FILE is required (or --calibrate-shift, --oracle)");
  if (family_size < 1 || family_size > 100000)
    return bad("--family-size " + std::to_string(family_size) + " is outside [1, 100000]");
  if (oracle && no_refit) return bad("--oracle needs the refit (drop --no-refit)");
  if (calibrate && o.family == truth::Family::kNone)
    return bad("--calibrate-shift needs a --family other than none");
  if (!out.empty()) {
    const std::string ext = std::filesystem::path(out).extension().string();
    if (ext != ".csv" && ext != ".h5") return bad("--out '" + out + "': use a .csv or .h5 file");
  }
  o.strength = strength;
  o.n = static_cast<std::size_t>(n);
  o.seed = seed;
  o.design = !states.empty()   ? truth::Design::kGiven
             : design == "lab" ? truth::Design::kLab
                               : truth::Design::kWide;
  o.id_prefix = id_prefix;
  if (scatter == "lab") {
    o.scatter_lo = truth::kScatterLabLo;
    o.scatter_hi = truth::kScatterLabHi;
  } else if (scatter != "narrow") {
    return bad("--scatter '" + scatter + "': use narrow or lab");
  }
  o.refit = !no_refit;
  if (engine_numerics) o.numerics = ricochet::truth::kEngineNumerics;
  o.oracle_family_size = static_cast<std::size_t>(family_size);
  o.contact_features = contact_features;
  o.tracks = tracks || !video_dir.empty();
  if (tracks && std::filesystem::path(out).extension() != ".h5")
    return bad("--tracks needs an .h5 --out (tracks are HDF5 datasets)");
  if (!(video.fps >= 50 && video.fps <= 1e5)) return bad("--video-fps is outside [50, 1e5]");
  if (!(video.noise_m >= 0 && video.noise_m <= 0.05))
    return bad("--video-noise-m is outside [0, 0.05] m");
  try {
    if (o.design == truth::Design::kGiven) {
      for (const auto& im : read_incident_states(states).impacts) o.given_vin.push_back(im.vin);
      o.n = o.given_vin.size();
      o.lab_source = states;
    }
    if (o.design == truth::Design::kLab) {
      o.lab_vin = truth::lab_cylinder_states(lab);
      o.lab_source = lab;
    }
    if (calibrate) {
      std::cout << truth::lab_scale_strength(o) << "\n";
      return 0;
    }
    const truth::TruthSet t = truth::make_set(o);
    if (oracle) std::cout << t.truth["oracle"].dump() << "\n";
    if (out.empty()) return 0;
    write_impact_set(t.set, out);
    if (tracks)
      for (std::size_t i = 0; i < t.tracks.size(); ++i)
        write_block_track(out, t.set.impacts[i].id, t.tracks[i]);
    if (!video_dir.empty()) {
      // The camera's own generator, so that the set is the same with or without a video.
      constexpr std::uint64_t kVideoSalt = 0x766964656fULL;  // "video"
      std::filesystem::create_directories(video_dir);
      for (std::size_t i = 0; i < t.tracks.size(); ++i) {
        const std::string path =
            (std::filesystem::path(video_dir) / (t.set.impacts[i].id + ".csv")).string();
        std::ofstream(path) << truth::video_csv(t.tracks[i], video, seed ^ kVideoSalt ^ i);
      }
    }
    if (truth_path.empty())
      truth_path = std::filesystem::path(out).replace_extension(".truth.json").string();
    nlohmann::json j = t.truth;
    std::string command;
    for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);
    j["command"] = command;
    j["set_file"] = out;
    std::ofstream f(truth_path);
    f << j.dump(1) << "\n";
    if (!f) throw std::runtime_error("cannot write " + truth_path);
  } catch (const std::exception& e) {
    std::cerr << "independent_truth: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
