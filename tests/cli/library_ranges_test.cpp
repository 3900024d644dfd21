// The options whose range the library decides (an options struct's problems(), common/
// option_problems.hpp): just outside each bound, the command line exits 2 with the library's
// message under its own option name, before any work; at a closed bound it goes on (to a missing
// input file, read only once the options are checked); --help shows the library's range. The
// ranges are read from the library's constants, so the command line and the library cannot
// disagree without this test failing. The library itself refuses the same options at the entry
// of the function consuming them, naming the field.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "diagnosis/diagnose.hpp"
#include "diagnosis/synth.hpp"
#include "diagnosis/throw_design.hpp"
#include "diagnosis/validation_report.hpp"
#include "engine/engine.hpp"
#include "fit/fit.hpp"
#include "stats/paired.hpp"
#include "support/program_test.hpp"
#include "transfer/transfer_io.hpp"
#include "uq/montecarlo.hpp"
#include "uq/sobol.hpp"

namespace ricochet {
namespace {

using test::quote;

const std::string kCyl = quote(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
const std::string kPlateau =
    quote(std::string(RICOCHET_SOURCE_DIR) + "/data/resolved/stiffness-plateau.h5");
// An input file that does not exist: a run that gets to reading it has accepted its options.
const std::string kMissing = "no-such-input.csv";

struct RangedOption {
  std::string help;     // the subcommand whose --help shows the option
  std::string command;  // with the arguments it needs besides the option
  std::string option;
  OptionRange range;
  double step = 1;        // how far outside a closed bound the values tried lie
  bool unsigned_ = true;  // CLI11 itself refuses a negative value (naming the option too)
  // `command` reading kMissing once its options are checked; empty: no closed bound to accept.
  std::string accepting = {};
  // The option's value as the command line takes it at the low and the high bound ("{}": the
  // number alone; a list option holds it among others).
  std::string lo_value = "{}", hi_value = "{}";
};

class LibraryRanges : public test::ProgramTest {
 protected:
  void expect_refused(const RangedOption& o, double value, const std::string& pattern) {
    const std::string args =
        fmt::format("{} {} {}", o.command, o.option, fmt::format(fmt::runtime(pattern), value));
    const test::RunResult r = ricochet(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.err;
    const std::string says =
        fmt::format("field '{}': value {} is outside {}", o.option, value, o.range.text());
    EXPECT_NE(r.err.find(says), std::string::npos)
        << args << "\nexpected: " << says << "\nstderr: " << r.err;
    EXPECT_TRUE(r.out.empty()) << args << "\nstdout: " << r.out;
  }
  // At a closed bound the option passes: the run stops at the missing input instead.
  void expect_accepted(const RangedOption& o, double value, const std::string& pattern) {
    // %.15g: an integer bound prints as one ("10000000", not "1e+07"), as an integer option reads.
    const std::string text = fmt::format(fmt::runtime(pattern), fmt::format("{:.15g}", value));
    const std::string args = fmt::format("{} {} {}", o.accepting, o.option, text);
    const test::RunResult r = ricochet(args);
    EXPECT_EQ(r.err.find("'" + o.option + "'"), std::string::npos) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(kMissing), std::string::npos) << args << "\nstderr: " << r.err;
    EXPECT_EQ(r.status, 2) << args << "\n" << r.err;
  }
};

TEST_F(LibraryRanges, EveryBoundIsTheLibrarysAndShownInHelp) {
  const std::string report = "report {} --out " + quote((dir_ / "r.html").string());
  const std::string design = "design {} --out " + quote((dir_ / "p.csv").string());
  const std::string synth = "synth --out " + quote((dir_ / "s.csv").string());
  const std::string paired = "paired {} --base E1.5e7- --against E1.5e8-";
  const std::string predict = "transfer predict --seed 1 --vin 2.9,-2.3,-65 --from {}";
  const auto on = [](const std::string& command, const std::string& data) {
    return fmt::format(fmt::runtime(command), data);
  };
  using diagnosis::AssessOptions, diagnosis::DiagnoseOptions, diagnosis::ReportOptions;
  using diagnosis::DesignOptions, diagnosis::SynthOptions, uq::MonteCarloOptions;
  using uq::RangeFitOptions, uq::SobolOptions;
  // The command line takes angles in degrees: the library's range in radians, converted.
  const auto degrees = [](OptionRange r) {
    r.lo *= 180 / M_PI;
    r.hi *= 180 / M_PI;
    return r;
  };
  const std::string no_compare = " --compare " + kMissing;
  const std::vector<RangedOption> options = {
      {"calibrate", "calibrate " + kCyl, "--starts", fit::FitOptions::kStarts, 1, false,
       "calibrate " + kMissing},
      {"calibrate", "calibrate " + kCyl, "--design-points", fit::FitOptions::kDesignPoints, 1,
       false, "calibrate " + kMissing},
      {"calibrate", "calibrate " + kCyl, "--threshold-scale", fit::FitOptions::kThresholdScale,
       1e-7, false, "calibrate " + kMissing},
      {"calibrate", "calibrate " + kCyl, "--alpha-range", degrees(fit::FitOptions::kAlphaRad), 1,
       false, "calibrate " + kMissing, "{},60", "-60,{}"},
      {"compare", "compare " + kCyl, "--repeats", AssessOptions::kRepeats, 1, true,
       "compare " + kMissing},
      {"compare", "compare " + kCyl, "--orientations", fit::FitOptions::kMarginalPoints, 1, false,
       "compare " + kMissing},
      {"compare", "compare " + kCyl, "--polish-orientations", fit::FitOptions::kPolishPoints, 1,
       false, "compare " + kMissing},
      {"compare", "compare " + kCyl, "--orientation-starts", fit::FitOptions::kStarts, 1, false,
       "compare " + kMissing},
      {"compare", "compare " + kCyl, "--search-xtol", fit::FitOptions::kUnitFraction, 1, false},
      {"design", on(design, kCyl), "--orientations", fit::FitOptions::kMarginalPoints, 1, false,
       on(design, kMissing)},
      {"design", on(design, kCyl), "--budget", DesignOptions::kBudget, 1, true,
       on(design, kMissing)},
      {"design", on(design, kCyl), "--candidates", DesignOptions::kCandidates, 1, true,
       on(design, kMissing) + " --budget 1"},
      {"design", on(design, kCyl), "--alpha", DesignOptions::kAlpha, 1e-7, false,
       on(design, kMissing)},
      {"design", on(design, kCyl), "--passes", DesignOptions::kPasses, 1, true,
       on(design, kMissing)},
      {"diagnose", "diagnose " + kCyl, "--alpha", DiagnoseOptions::kAlpha, 1, false},
      {"diagnose", "diagnose " + kCyl, "--screen", DiagnoseOptions::kScreen, 1, true,
       "diagnose " + kMissing},
      {"diagnose", "diagnose " + kCyl, "--adequate-z", DiagnoseOptions::kAdequateZ, 1, false,
       "diagnose " + kMissing},
      {"ladder", "ladder " + kCyl + " --add rate_restitution", "--repeats", AssessOptions::kRepeats,
       1, true, "ladder " + kMissing + " --add rate_restitution"},
      {"report", on(report, kCyl), "--rounds", ReportOptions::kRounds, 1, false,
       on(report, kMissing)},
      {"report", on(report, kCyl), "--alpha", DiagnoseOptions::kAlpha, 1, false},
      {"transfer fit", "transfer fit " + kCyl, "--replicates", transfer::FitSampling::kReplicates,
       1, true, "transfer fit " + kMissing},
      {"transfer predict", on(predict, kCyl), "--n", transfer::PredictSampling::kReplicates, 1,
       true, on(predict, kMissing)},
      // The engine's time step, on every command running the engine (model_options.cpp).
      {"simulate", "simulate --vin 2.9,-2.3,-65", "--dt", EngineOptions::kDt, 1, false},
      {"montecarlo", "montecarlo", "--dt", EngineOptions::kDt, 1, false},
      {"diagnose", "diagnose " + kCyl, "--dt", EngineOptions::kDt, 1, false},
      {"design", on(design, kCyl), "--dt", EngineOptions::kDt, 1, false},
      {"montecarlo", "montecarlo", "--n", MonteCarloOptions::kRuns, 1, true,
       "montecarlo" + no_compare},
      {"montecarlo", "montecarlo", "--alpha-range", degrees(MonteCarloOptions::kAlphaRad), 1, false,
       "montecarlo" + no_compare, "{},60", "-60,{}"},
      {"montecarlo", "montecarlo", "--range-runs", MonteCarloOptions::kRuns, 1, true,
       "montecarlo" + no_compare},
      {"montecarlo", "montecarlo", "--range-evaluations", RangeFitOptions::kMaxEvaluations, 1,
       false, "montecarlo" + no_compare},
      {"sobol", "sobol", "--n", SobolOptions::kBaseSize, 1, true,
       "sobol --range " + kMissing + "=0:1"},
      {"sobol", "sobol", "--bootstrap", SobolOptions::kBootstrap, 1, true,
       "sobol --range " + kMissing + "=0:1"},
      {"sobol", "sobol", "--confidence", SobolOptions::kConfidence, 1, false},
      {"synth", synth, "--n", SynthOptions::kN, 1, true, synth + " --incident " + kMissing},
      {"paired", on(paired, kPlateau), "--margin", stats::PairedOptions::kMargin, 1, false,
       on(paired, kMissing)},
      {"paired", on(paired, kPlateau), "--level", stats::PairedOptions::kLevel, 1, false},
  };
  for (const RangedOption& o : options) {
    const double below = o.range.lo_open ? o.range.lo : o.range.lo - o.step;
    if (below >= 0 || !o.unsigned_) expect_refused(o, below, o.lo_value);
    // An unbounded range has nothing above it.
    if (std::isfinite(o.range.hi))
      expect_refused(o, o.range.hi_open ? o.range.hi : o.range.hi + o.step, o.hi_value);
    if (!o.accepting.empty()) {
      if (!o.range.lo_open) expect_accepted(o, o.range.lo, o.lo_value);
      if (!o.range.hi_open) expect_accepted(o, o.range.hi, o.hi_value);
    }
    const test::RunResult help = ricochet(o.help + " --help");
    ASSERT_EQ(help.status, 0) << o.help;
    EXPECT_NE(help.out.find("in " + o.range.text()), std::string::npos)
        << o.help << " --help does not show " << o.option << " in " << o.range.text() << "\n"
        << help.out;
  }
}

// A program calling the library gets the refusal the command line prints: InputError naming the
// options struct's field, thrown at the consuming function's entry (empty inputs: before any
// work).
TEST(LibraryRefusals, EachConsumerNamesTheField) {
  const Model paper = Model::paper();
  const Shape cyl = Shape::cylinder();
  const auto expect_field = [](const std::string& consumer, const std::string& field,
                               const std::function<void()>& call) {
    try {
      call();
      ADD_FAILURE() << consumer << " accepted a bad " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << consumer << ": " << e.what();
      EXPECT_NE(e.file().find(consumer), std::string::npos) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << consumer << " refused a bad " << field
                    << " later, not by name: " << e.what();
    }
  };
  const CollisionCase lab{{2.9, -2.3, -65}, 0};
  expect_field("simulate", "dt_s", [&] {
    EngineOptions e;
    e.dt_s = EngineOptions::kDt.hi;
    (void)simulate(paper, cyl, lab, {}, e);
  });
  expect_field("simulate_batch", "max_time_s", [&] {
    EngineOptions e;
    e.max_time_s = 0;
    (void)simulate_batch(paper, cyl, std::vector<CollisionCase>{lab}, {}, e);
  });
  expect_field("uq::run_monte_carlo", "runs", [&] {
    uq::MonteCarloOptions o;
    o.runs = 1;
    (void)uq::run_monte_carlo(paper, cyl, {}, o);
  });
  expect_field("uq::run_monte_carlo", "engine.dt_s", [&] {
    uq::MonteCarloOptions o;
    o.engine.dt_s = 0;
    (void)uq::run_monte_carlo(paper, cyl, {}, o);
  });
  expect_field("uq::calibrate_ranges", "mc.runs", [&] {
    uq::RangeFitOptions o;
    o.mc.runs = 0;
    (void)uq::calibrate_ranges(paper, cyl, ImpactSet{}, {}, o);
  });
  expect_field("uq::sobol_indices", "bootstrap", [&] {
    uq::SobolOptions o;
    o.bootstrap = 1;
    (void)uq::sobol_indices(uq::ishigami(), {}, {}, o);
  });
  expect_field("uq::collision_sobol", "engine.dt_s", [&] {
    EngineOptions e;
    e.dt_s = -1;
    (void)uq::collision_sobol(paper, cyl, {}, lab.vin, 0, {}, e);
  });
  expect_field("diagnosis::synthesize", "n", [&] {
    diagnosis::SynthOptions o;
    o.n = 0;
    (void)diagnosis::synthesize(paper, cyl, o);
  });
  expect_field("diagnosis::synthesize", "wide.vin_y", [&] {
    diagnosis::SynthOptions o;
    o.wide.vin_y = {-2, 1};
    (void)diagnosis::synthesize(paper, cyl, o);
  });
  expect_field("diagnosis::design_throws", "candidates", [&] {
    diagnosis::DesignOptions o;
    o.candidates = o.budget - 1;
    (void)diagnosis::design_throws(paper, cyl, ImpactSet{}, {}, diagnosis::WideBox{}, o);
  });
  expect_field("diagnosis::design_throws", "assess.fit.engine.dt_s", [&] {
    diagnosis::DesignOptions o;
    o.assess.fit.engine.dt_s = 1;
    (void)diagnosis::design_throws(paper, cyl, ImpactSet{}, {}, diagnosis::WideBox{}, o);
  });
  expect_field("diagnosis::design_throws", "box.vin_x", [&] {
    diagnosis::WideBox box;
    box.vin_x = {3, 2};
    (void)diagnosis::design_throws(paper, cyl, ImpactSet{}, {}, box, {});
  });
  expect_field("diagnosis::assess", "fit.engine.dt_s", [&] {
    diagnosis::AssessOptions o;
    o.fit.engine.dt_s = 0;
    (void)diagnosis::assess(paper, cyl, ImpactSet{}, o);
  });
  expect_field("stats::paired_comparison", "level", [&] {
    stats::PairedOptions o;
    o.level = 1;
    (void)stats::paired_comparison(ImpactSet{}, "A-", "B-", {}, o);
  });
  expect_field("transfer::sample_predictions", "replicates", [&] {
    transfer::PredictReport r;
    transfer::PredictSampling s;
    s.replicates = 0;
    transfer::sample_predictions(r, transfer::PredictIncidents::kGivenState, s);
  });
}

}  // namespace
}  // namespace ricochet
