// Each default of a command-line option lives in one place, the library's option struct: the
// default --help shows (CLI11's "--name TYPE=DEFAULT") is the struct's default member value, on
// every command (EveryCommandsShownDefaultsAreChecked finds the commands and the defaults they
// show through --help). Where two layers differ on purpose, the difference is named once in the
// library and checked here as such.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"
#include "diagnosis/inputs.hpp"
#include "diagnosis/synth.hpp"
#include "diagnosis/throw_design.hpp"
#include "diagnosis/validation_report.hpp"
#include "engine/engine.hpp"
#include "engine/shape.hpp"
#include "fit/fit.hpp"
#include "kinematics/reconstruct.hpp"
#include "kinematics/track_forces.hpp"
#include "stats/lab_gap.hpp"
#include "stats/paired.hpp"
#include "support/program_test.hpp"
#include "transfer/transfer_io.hpp"
#include "uq/montecarlo.hpp"
#include "uq/sobol.hpp"
#if RICOCHET_HAVE_LIGGGHTS
#include "grain_calibration.hpp"
#include "impact_run.hpp"
#include "impact_spec.hpp"
#include "upscale.hpp"
#endif

namespace ricochet {
namespace {

class OptionDefaults : public test::ProgramTest {
 protected:
  // `ricochet COMMAND --help`, run once per command.
  const std::string& help(const std::string& command) {
    auto it = helps_.find(command);
    if (it != helps_.end()) return it->second;
    const test::RunResult r = ricochet(command + " --help");
    EXPECT_EQ(r.status, 0) << command << "\n" << r.err;
    return helps_[command] = r.out;
  }
  // Each option line of `command`'s help and the default it shows ("" when it shows none).
  // CLI11 writes "  --starts INT:in [1, 1000]=4   BOBYQA ...": the default follows the first '='
  // of the option's signature, which ends at the first double space (the description may hold
  // '=' of its own, "NAME=VALUE").
  std::map<std::string, std::string> defaults(const std::string& command) {
    std::map<std::string, std::string> out;
    std::istringstream lines(help(command));
    std::string line;
    while (std::getline(lines, line)) {
      if (!line.starts_with("  --")) continue;
      const std::string signature = line.substr(2, line.find("  ", 2) - 2);
      const std::string name = signature.substr(0, signature.find(' '));
      const auto eq = signature.find('=');
      out[name] =
          eq == std::string::npos ? "" : signature.substr(eq + 1, signature.find(' ', eq) - eq - 1);
    }
    return out;
  }
  // The default `ricochet COMMAND --help` shows for `option` ("" when it shows none).
  std::string shown(const std::string& command, const std::string& option) {
    checked_.insert(command + " " + option);
    const auto all = defaults(command);
    const auto it = all.find(option);
    if (it == all.end()) ADD_FAILURE() << command << " --help has no " << option;
    return it == all.end() ? "" : it->second;
  }
  void expect(const std::string& command, const std::string& option, double library) {
    const std::string text = shown(command, option);
    ASSERT_FALSE(text.empty()) << command << " " << option << " shows no default";
    EXPECT_DOUBLE_EQ(std::stod(text), library) << command << " " << option << " shows " << text;
  }
  void expect(const std::string& command, const std::string& option, const std::string& library) {
    EXPECT_EQ(shown(command, option), library) << command << " " << option;
  }

  // The checks, one per library module; each test runs its own, and the last one runs them all
  // to know which defaults they cover.
  void calibrate();
  void diagnosis();
  void transfer();
  void uncertainty();
  void synth();
  void engine();
  void paired();
  void reconstruct();
  void resolved_model();

  std::set<std::string> checked_;  // "COMMAND --option" of every default checked
  std::map<std::string, std::string> helps_;
};

void OptionDefaults::calibrate() {
  const fit::FitOptions f;
  expect("calibrate", "--seed", static_cast<double>(f.seed));
  expect("calibrate", "--starts", f.starts);
  expect("calibrate", "--design-points", f.design_points);
  expect("calibrate", "--threshold-scale", f.threshold_scale);
  expect("calibrate", "--alpha", fit::alpha_mode_name(f.alpha.mode));
  expect("calibrate", "--threads", f.threads);
  expect("calibrate", "--dt", f.engine.dt_s);
}

void OptionDefaults::diagnosis() {
  const diagnosis::DiagnoseOptions d;
  const diagnosis::AssessOptions& a = d.assess;
  for (const std::string command : {"compare", "diagnose", "ladder", "report"}) {
    expect(command, "--folds", std::to_string(a.folds));
    expect(command, "--seed", static_cast<double>(a.fit.seed));
    expect(command, "--repeats", static_cast<double>(a.repeats));
    expect(command, "--error", diagnosis::error_scale_name(a.scale));
    expect(command, "--orientations", a.fit.alpha.marginal_points);
    expect(command, "--polish-orientations", a.fit.alpha.polish_points);
    expect(command, "--orientation-starts", a.marginal_starts);
    expect(command, "--search-xtol", a.fit.alpha.search_xtol);
    expect(command, "--orientation-search", fit::orientation_search_name(a.fit.alpha.search));
    expect(command, "--threads", a.fit.threads);
    expect(command, "--dt", a.fit.engine.dt_s);
  }
  for (const std::string command : {"diagnose", "ladder", "report"}) {
    expect(command, "--alpha", d.alpha);
    expect(command, "--screen", static_cast<double>(d.screen));
    expect(command, "--adequate-z", d.adequate_z);
  }
  const diagnosis::ReportOptions r;
  expect("report", "--rounds", r.rounds);
  // CLI11 shows a string default with its spaces: the signature ends at the first double space.
  EXPECT_NE(help("report").find("--title TEXT=" + r.title), std::string::npos) << help("report");
  checked_.insert("report --title");
  const diagnosis::DesignOptions de;
  expect("design", "--budget", static_cast<double>(de.budget));
  expect("design", "--candidates", static_cast<double>(de.candidates));
  expect("design", "--alpha", de.alpha);
  expect("design", "--passes", static_cast<double>(de.max_passes));
  expect("design", "--seed", static_cast<double>(de.seed));
  expect("design", "--orientations", de.assess.fit.alpha.marginal_points);
  expect("design", "--polish-orientations", de.assess.fit.alpha.polish_points);
  expect("design", "--threads", de.assess.fit.threads);
  expect("design", "--dt", de.assess.fit.engine.dt_s);
  // The command line's values, before any parse, build the library's options unchanged.
  const diagnosis::DiagnoseOptions made = diagnosis::make_options(diagnosis::OptionValues{});
  EXPECT_EQ(made.assess.fit.alpha.marginal_points, a.fit.alpha.marginal_points);
  EXPECT_EQ(made.assess.fit.alpha.polish_points, a.fit.alpha.polish_points);
  EXPECT_EQ(made.assess.marginal_starts, a.marginal_starts);
  EXPECT_EQ(made.assess.fit.seed, a.fit.seed);
  EXPECT_EQ(made.assess.repeats, a.repeats);
  EXPECT_EQ(made.assess.scale, a.scale);
  EXPECT_EQ(made.alpha, d.alpha);
  EXPECT_EQ(made.screen, d.screen);
  EXPECT_EQ(made.adequate_z, d.adequate_z);
  EXPECT_EQ(made.pairs, d.pairs);
  EXPECT_EQ(made.assess.release_fits, a.release_fits);
  EXPECT_EQ(made.assess.release_intervals, a.release_intervals);
  EXPECT_EQ(made.assess.use_features, a.use_features);
  EXPECT_EQ(made.assess.fit.engine.dt_s, a.fit.engine.dt_s);
  EXPECT_EQ(made.assess.folds, a.folds);
}

void OptionDefaults::transfer() {
  const transfer::FitSampling s;
  expect("transfer fit", "--seed", static_cast<double>(s.seed));
  expect("transfer fit", "--replicates", static_cast<double>(s.replicates));
  const transfer::PredictSampling p;
  expect("transfer predict", "--seed", static_cast<double>(p.seed));
  // --n's default depends on the incident states, so the help says both, from the library.
  EXPECT_NE(help("transfer predict")
                .find(fmt::format("default {} with --vin, {} with --incident",
                                  transfer::PredictSampling::kGivenStateReplicates,
                                  transfer::PredictSampling::kMeasuredSetReplicates)),
            std::string::npos)
      << help("transfer predict");
  EXPECT_EQ(p.replicates_for(transfer::PredictIncidents::kGivenState),
            transfer::PredictSampling::kGivenStateReplicates);
  EXPECT_EQ(p.replicates_for(transfer::PredictIncidents::kMeasuredSet),
            transfer::PredictSampling::kMeasuredSetReplicates);
}

void OptionDefaults::uncertainty() {
  const uq::MonteCarloOptions mc;
  const uq::RangeFitOptions rf;
  expect("montecarlo", "--n", static_cast<double>(mc.runs));
  expect("montecarlo", "--seed", static_cast<double>(mc.seed));
  expect("montecarlo", "--threads", mc.engine.threads);
  expect("montecarlo", "--dt", mc.engine.dt_s);
  expect("montecarlo", "--range-runs", static_cast<double>(rf.mc.runs));
  expect("montecarlo", "--range-evaluations", rf.max_evaluations);
  expect("montecarlo", "--distance", "cvm");
  EXPECT_EQ(rf.distance, uq::RangeFitOptions::Distance::kCramerVonMises);
  EXPECT_NE(help("montecarlo")
                .find(fmt::format("(default {:g},{:g})", mc.alpha_min_rad * 180 / M_PI,
                                  mc.alpha_max_rad * 180 / M_PI)),
            std::string::npos);
  const uq::SobolOptions so;
  expect("sobol", "--n", static_cast<double>(so.base_size));
  expect("sobol", "--seed", static_cast<double>(so.seed));
  expect("sobol", "--bootstrap", static_cast<double>(so.bootstrap));
  expect("sobol", "--confidence", so.confidence);
  expect("sobol", "--estimator", uq::estimator_name(so.estimator));
  // Sobol explores the model around the Monte Carlo's collision, with its engine settings.
  expect("sobol", "--threads", mc.engine.threads);
  expect("sobol", "--dt", mc.engine.dt_s);
}

void OptionDefaults::synth() {
  const diagnosis::SynthOptions sy;
  expect("synth", "--n", static_cast<double>(sy.n));
  expect("synth", "--seed", static_cast<double>(sy.seed));
  expect("synth", "--design", diagnosis::design_name(sy.design));
  expect("synth", "--threads", sy.engine.threads);
  expect("synth", "--dt", sy.engine.dt_s);
  // --noise lab is the library's default noise; --features lists every feature it writes.
  expect("synth", "--noise", "lab");
  EXPECT_EQ(diagnosis::NoiseSpec::parse("lab").vout, sy.noise.vout);
  EXPECT_EQ(diagnosis::NoiseSpec::parse("lab").contact_duration_s, sy.noise.contact_duration_s);
  expect("synth", "--features", "alpha_in,penetration,contact_duration");
  EXPECT_TRUE(sy.write_alpha && sy.write_penetration && sy.write_contact_duration);
}

// Every command running the engine takes --dt and --shape (model_options.cpp): the engine's
// step, and the lab cylinder.
void OptionDefaults::engine() {
  const EngineOptions e;
  expect("simulate", "--dt", e.dt_s);
  for (const std::string command : {"simulate", "calibrate", "montecarlo", "sobol", "synth",
                                    "compare", "diagnose", "ladder", "design", "report"})
    expect(command, "--shape", Shape::cylinder().name);
}

void OptionDefaults::paired() {
  const stats::PairedOptions p;
  expect("paired", "--level", p.level);
  expect("paired", "--margin", p.margin);
}

void OptionDefaults::reconstruct() {
  const kinematics::ReconstructOptions rc;
  expect("reconstruct", "--k-sigma", rc.detection_k_sigma);
  expect("reconstruct", "--guard", static_cast<double>(rc.detection_guard_points));
  expect("reconstruct", "--smooth",
         static_cast<double>(kinematics::TrackForceOptions{}.half_window));
  EXPECT_NE(help("reconstruct").find(fmt::format("(default {:g})", rc.gravity_mps2.value_or(0))),
            std::string::npos);
  // The label written into the impact set's shape column when none is given: the command
  // line's own, no library option holds it.
  expect("reconstruct", "--shape", "unknown");
}

void OptionDefaults::resolved_model() {
#if RICOCHET_HAVE_LIGGGHTS
  if (!test::program_has_liggghts()) return;
  const dem::UpscaleOptions u;
  expect("upscale", "--seed", static_cast<double>(u.fit.seed));
  expect("upscale", "--starts", u.fit.starts);
  expect("upscale", "--threads", u.fit.threads);
  expect("upscale", "--dt", u.fit.engine.dt_s);
  expect("upscale", "--shape", Shape::cylinder().name);
  expect("upscale", "--lab-noise-draws", static_cast<double>(stats::LabGapOptions{}.noise_draws));
  expect("calibrate-grains", "--seed", static_cast<double>(dem::GrainCalibrationOptions{}.seed));
  expect("calibrate-grains", "--rebound-threshold",
         dem::GrainCalibrationOptions{}.rebound_threshold);
  const Vel3 vin = dem::ImpactSpec{}.vin;
  std::ostringstream text;
  text << vin[0] << "," << vin[1] << "," << vin[2];
  expect("dem impact", "--vin", text.str());
  expect("dem impact", "--shape", dem::ImpactSpec{}.shape);
  expect("dem impact", "--fps", dem::ExtractOptions{}.fps);
  for (const std::string command : {"dem impact", "dem campaign"})
    expect(command, "--vtk-every", static_cast<double>(dem::kDefaultVtkEvery));
  // The resolved impact's default incident state is the Monte Carlo's (the lab mean).
  EXPECT_EQ(vin, uq::MonteCarloOptions{}.vin);
#endif
}

TEST_F(OptionDefaults, CalibrateShowsTheFitModulesDefaults) {
  calibrate();
}

TEST_F(OptionDefaults, DiagnosisCommandsShowTheDiagnosisDefaults) {
  diagnosis();
}

TEST_F(OptionDefaults, TransferCommandsShowTheirLibraryDefaults) {
  transfer();
}

TEST_F(OptionDefaults, UncertaintyCommandsShowTheUqDefaults) {
  uncertainty();
}

TEST_F(OptionDefaults, SynthShowsTheSynthDefaults) {
  synth();
}

TEST_F(OptionDefaults, EngineCommandsShowTheEngineDefaults) {
  engine();
}

TEST_F(OptionDefaults, PairedShowsTheStatsDefaults) {
  paired();
}

TEST_F(OptionDefaults, ReconstructShowsTheKinematicsDefaults) {
  reconstruct();
}

#if RICOCHET_HAVE_LIGGGHTS
TEST_F(OptionDefaults, ResolvedModelCommandsShowTheirLibraryDefaults) {
  if (!test::program_has_liggghts()) GTEST_SKIP() << "this ricochet has no LIGGGHTS";
  resolved_model();
}
#endif

// Every command, found through --help (so a new one is covered too): each default its --help
// shows is one the checks above compare with the library. stats and effects show none.
TEST_F(OptionDefaults, EveryCommandsShownDefaultsAreChecked) {
  calibrate();
  diagnosis();
  transfer();
  uncertainty();
  synth();
  engine();
  paired();
  reconstruct();
  resolved_model();
  std::vector<std::string> commands;
  const auto add_subcommands = [&](auto&& self, const std::string& parent) -> void {
    std::istringstream lines(help(parent));
    std::string line;
    bool in_list = false;
    while (std::getline(lines, line)) {
      if (line == "Subcommands:") {
        in_list = true;
        continue;
      }
      if (!in_list) continue;
      if (!line.starts_with("  ")) {  // the list ends at the first line that is not an entry
        in_list = false;
        continue;
      }
      const std::string name = line.substr(2, line.find(' ', 2) - 2);
      const std::string command = parent.empty() ? name : parent + " " + name;
      commands.push_back(command);
      self(self, command);
    }
  };
  add_subcommands(add_subcommands, "");
  ASSERT_GE(commands.size(), 15u) << help("");
  for (const std::string& command : commands) {
    if (test::needs_liggghts(command) && !test::program_has_liggghts()) continue;
    for (const auto& [option, value] : defaults(command)) {
      if (value.empty()) continue;
      EXPECT_TRUE(checked_.count(command + " " + option))
          << command << " " << option << " shows the default " << value
          << " that no check compares with the library";
    }
  }
}

// The deliberate differences between layers, each named once in the library.
TEST(OptionLayers, DeliberateDifferencesAreNamedOnce) {
  // Bulk runs on lab collisions stop a rebound at 0.1 s; a single `simulate` at 0.5 s
  // (engine.hpp, bulk_engine_options).
  const double bulk = bulk_engine_options().max_time_s;
  EXPECT_LT(bulk, EngineOptions{}.max_time_s);
  EXPECT_EQ(fit::FitOptions{}.engine.max_time_s, bulk);
  EXPECT_EQ(uq::MonteCarloOptions{}.engine.max_time_s, bulk);
  EXPECT_EQ(diagnosis::SynthOptions{}.engine.max_time_s, bulk);
  EXPECT_EQ(diagnosis::AssessOptions{}.fit.engine.max_time_s, bulk);
  // Otherwise the bulk settings are the engine's.
  EXPECT_EQ(bulk_engine_options().dt_s, EngineOptions{}.dt_s);
  // The diagnosis averages over the same orientation rules as a calibration (issue 35: one
  // converged rule, docs/diagnosis.md "Orientation average"), and its cold fits of sets of
  // unknown orientation run more starts than the fit module's default.
  EXPECT_EQ(diagnosis::AssessOptions{}.fit.alpha.marginal_points,
            fit::FitOptions{}.alpha.marginal_points);
  EXPECT_EQ(diagnosis::AssessOptions{}.fit.alpha.polish_points,
            fit::FitOptions{}.alpha.polish_points);
  EXPECT_GT(diagnosis::AssessOptions{}.marginal_starts, fit::FitOptions{}.starts);
  // Its population fit runs more starts than a release fit (AssessOptions::population_starts:
  // the population objective is multimodal in mu).
  EXPECT_GT(diagnosis::AssessOptions{}.population_starts, fit::FitOptions{}.starts);
  // Everything else of the diagnosis's fit settings is the fit module's.
  EXPECT_EQ(diagnosis::AssessOptions{}.fit.starts, fit::FitOptions{}.starts);
  EXPECT_EQ(diagnosis::AssessOptions{}.fit.seed, fit::FitOptions{}.seed);
}

}  // namespace
}  // namespace ricochet
