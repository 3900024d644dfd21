// Each default of a command-line option lives in one place, the library's option struct: the
// default --help shows (CLI11's "--name TYPE=DEFAULT") is the struct's default member value.
// Where two layers differ on purpose, the difference is named once in the library and checked
// here as such.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "diagnosis/diagnose.hpp"
#include "diagnosis/inputs.hpp"
#include "diagnosis/synth.hpp"
#include "diagnosis/throw_design.hpp"
#include "diagnosis/validation_report.hpp"
#include "engine/engine.hpp"
#include "fit/fit.hpp"
#include "kinematics/reconstruct.hpp"
#include "support/program_test.hpp"
#include "transfer/transfer_io.hpp"
#include "uq/montecarlo.hpp"
#include "uq/sobol.hpp"
#if RICOCHET_HAVE_LIGGGHTS
#include "grain_calibration.hpp"
#include "impact_spec.hpp"
#include "upscale.hpp"
#endif

namespace ricochet {
namespace {

class OptionDefaults : public test::ProgramTest {
 protected:
  // The default `ricochet COMMAND --help` shows for `option` ("" when it shows none).
  std::string shown(const std::string& command, const std::string& option) {
    const test::RunResult r = ricochet(command + " --help");
    EXPECT_EQ(r.status, 0) << command << "\n" << r.err;
    std::istringstream lines(r.out);
    std::string line;
    while (std::getline(lines, line)) {
      const auto at = line.find("  " + option + " ");
      if (at != 0) continue;
      // "  --starts INT:in [1, 1000]=4 BOBYQA ...": the text after the first '=' up to a blank.
      const auto eq = line.find('=', at + option.size());
      if (eq == std::string::npos) return "";
      return line.substr(eq + 1, line.find(' ', eq) - eq - 1);
    }
    ADD_FAILURE() << command << " --help has no " << option << "\n" << r.out;
    return "";
  }
  void expect(const std::string& command, const std::string& option, double library) {
    const std::string text = shown(command, option);
    ASSERT_FALSE(text.empty()) << command << " " << option << " shows no default";
    EXPECT_DOUBLE_EQ(std::stod(text), library) << command << " " << option << " shows " << text;
  }
  void expect(const std::string& command, const std::string& option, const std::string& library) {
    EXPECT_EQ(shown(command, option), library) << command << " " << option;
  }
};

TEST_F(OptionDefaults, CalibrateShowsTheFitModulesDefaults) {
  const fit::FitOptions f;
  expect("calibrate", "--seed", static_cast<double>(f.seed));
  expect("calibrate", "--starts", f.starts);
  expect("calibrate", "--design-points", f.design_points);
  expect("calibrate", "--threshold-scale", f.threshold_scale);
  expect("calibrate", "--alpha", fit::alpha_mode_name(f.alpha.mode));
  expect("calibrate", "--threads", f.threads);
  expect("calibrate", "--dt", f.engine.dt_s);
}

TEST_F(OptionDefaults, DiagnosisCommandsShowTheDiagnosisDefaults) {
  const diagnosis::DiagnoseOptions d;
  const diagnosis::AssessOptions& a = d.assess;
  for (const std::string command : {"compare", "diagnose", "ladder", "report"}) {
    expect(command, "--folds", std::to_string(a.folds));
    expect(command, "--seed", static_cast<double>(a.fit.seed));
    expect(command, "--repeats", static_cast<double>(a.repeats));
    expect(command, "--error", diagnosis::error_scale_name(a.scale));
    expect(command, "--orientations", a.fit.alpha.marginal_points);
    expect(command, "--threads", a.fit.threads);
    expect(command, "--dt", a.fit.engine.dt_s);
  }
  expect("diagnose", "--alpha", d.alpha);
  expect("diagnose", "--screen", static_cast<double>(d.screen));
  expect("report", "--alpha", d.alpha);
  expect("ladder", "--alpha", d.alpha);
  expect("report", "--rounds", diagnosis::ReportOptions{}.rounds);
  const diagnosis::DesignOptions de;
  expect("design", "--budget", static_cast<double>(de.budget));
  expect("design", "--candidates", static_cast<double>(de.candidates));
  expect("design", "--alpha", de.alpha);
  expect("design", "--passes", static_cast<double>(de.max_passes));
  expect("design", "--seed", static_cast<double>(de.seed));
  expect("design", "--orientations", de.assess.fit.alpha.marginal_points);
  expect("design", "--threads", de.assess.fit.threads);
  // The command line's values, before any parse, build the library's options unchanged.
  const diagnosis::DiagnoseOptions made = diagnosis::make_options(diagnosis::OptionValues{});
  EXPECT_EQ(made.assess.fit.alpha.marginal_points, a.fit.alpha.marginal_points);
  EXPECT_EQ(made.assess.fit.seed, a.fit.seed);
  EXPECT_EQ(made.assess.repeats, a.repeats);
  EXPECT_EQ(made.assess.scale, a.scale);
  EXPECT_EQ(made.alpha, d.alpha);
  EXPECT_EQ(made.screen, d.screen);
  EXPECT_EQ(made.pairs, d.pairs);
  EXPECT_EQ(made.assess.release_fits, a.release_fits);
  EXPECT_EQ(made.assess.release_intervals, a.release_intervals);
  EXPECT_EQ(made.assess.use_features, a.use_features);
  EXPECT_EQ(made.assess.fit.engine.dt_s, a.fit.engine.dt_s);
  EXPECT_EQ(made.assess.folds, a.folds);
}

TEST_F(OptionDefaults, TransferFitShowsItsLibraryDefaults) {
  const transfer::FitSampling s;
  expect("transfer fit", "--seed", static_cast<double>(s.seed));
  expect("transfer fit", "--replicates", static_cast<double>(s.replicates));
}

TEST_F(OptionDefaults, UncertaintyCommandsShowTheUqDefaults) {
  const uq::MonteCarloOptions mc;
  const uq::RangeFitOptions rf;
  expect("montecarlo", "--n", static_cast<double>(mc.runs));
  expect("montecarlo", "--seed", static_cast<double>(mc.seed));
  expect("montecarlo", "--threads", mc.engine.threads);
  expect("montecarlo", "--range-runs", static_cast<double>(rf.mc.runs));
  expect("montecarlo", "--range-evaluations", rf.max_evaluations);
  const uq::SobolOptions so;
  expect("sobol", "--n", static_cast<double>(so.base_size));
  expect("sobol", "--seed", static_cast<double>(so.seed));
  expect("sobol", "--bootstrap", static_cast<double>(so.bootstrap));
  expect("sobol", "--confidence", so.confidence);
  expect("sobol", "--estimator", uq::estimator_name(so.estimator));
  const diagnosis::SynthOptions sy;
  expect("synth", "--n", static_cast<double>(sy.n));
  expect("synth", "--seed", static_cast<double>(sy.seed));
  const kinematics::ReconstructOptions rc;
  expect("reconstruct", "--k-sigma", rc.detection_k_sigma);
  expect("reconstruct", "--guard", static_cast<double>(rc.detection_guard_points));
}

#if RICOCHET_HAVE_LIGGGHTS
TEST_F(OptionDefaults, ResolvedModelCommandsShowTheirLibraryDefaults) {
  const dem::UpscaleOptions u;
  expect("upscale", "--seed", static_cast<double>(u.fit.seed));
  expect("upscale", "--starts", u.fit.starts);
  expect("upscale", "--threads", u.fit.threads);
  expect("calibrate-grains", "--seed", static_cast<double>(dem::GrainCalibrationOptions{}.seed));
  const Vel3 vin = dem::ImpactSpec{}.vin;
  std::ostringstream text;
  text << vin[0] << "," << vin[1] << "," << vin[2];
  expect("dem impact", "--vin", text.str());
  expect("dem impact", "--shape", dem::ImpactSpec{}.shape);
  expect("dem impact", "--fps", dem::ExtractOptions{}.fps);
  // The resolved impact's default incident state is the Monte Carlo's (the lab mean).
  EXPECT_EQ(vin, uq::MonteCarloOptions{}.vin);
}
#endif

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
  // The diagnosis's screen averages fewer orientations than a calibration (AssessOptions::fit:
  // half the time, the same held-out error within 1 %).
  EXPECT_LT(diagnosis::AssessOptions{}.fit.alpha.marginal_points,
            fit::FitOptions{}.alpha.marginal_points);
  // Its population fit runs more starts than a release fit (AssessOptions::population_starts:
  // the population objective is multimodal in mu).
  EXPECT_GT(diagnosis::AssessOptions{}.population_starts, fit::FitOptions{}.starts);
  // Everything else of the diagnosis's fit settings is the fit module's.
  EXPECT_EQ(diagnosis::AssessOptions{}.fit.starts, fit::FitOptions{}.starts);
  EXPECT_EQ(diagnosis::AssessOptions{}.fit.seed, fit::FitOptions{}.seed);
}

}  // namespace
}  // namespace ricochet
