// The options whose range the library decides (an options struct's problems(), common/
// option_problems.hpp): just outside each bound, the command line exits 2 with the library's
// message under its own option name, before any work; --help shows the library's range. The
// ranges are read from the library's constants, so the command line and the library cannot
// disagree without this test failing.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>
#include <vector>

#include "diagnosis/diagnose.hpp"
#include "diagnosis/validation_report.hpp"
#include "fit/fit.hpp"
#include "support/program_test.hpp"
#include "transfer/transfer_io.hpp"

namespace ricochet {
namespace {

using test::quote;

const std::string kCyl = quote(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");

struct RangedOption {
  std::string help;     // the subcommand whose --help shows the option
  std::string command;  // with the arguments it needs besides the option
  std::string option;
  OptionRange range;
  double step = 1;        // how far outside a closed bound the values tried lie
  bool unsigned_ = true;  // CLI11 itself refuses a negative value (naming the option too)
};

class LibraryRanges : public test::ProgramTest {
 protected:
  void expect_refused(const RangedOption& o, double value) {
    const std::string args = fmt::format("{} {} {}", o.command, o.option, value);
    const test::RunResult r = ricochet(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.err;
    const std::string says =
        fmt::format("field '{}': value {} is outside {}", o.option, value, o.range.text());
    EXPECT_NE(r.err.find(says), std::string::npos)
        << args << "\nexpected: " << says << "\nstderr: " << r.err;
    EXPECT_TRUE(r.out.empty()) << args << "\nstdout: " << r.out;
  }
};

TEST_F(LibraryRanges, EveryBoundIsTheLibrarysAndShownInHelp) {
  const std::string report = "report " + kCyl + " --out " + quote((dir_ / "r.html").string());
  const std::string design = "design " + kCyl + " --out " + quote((dir_ / "p.csv").string());
  using diagnosis::AssessOptions, diagnosis::DiagnoseOptions, diagnosis::ReportOptions;
  const std::vector<RangedOption> options = {
      {"calibrate", "calibrate " + kCyl, "--starts", fit::FitOptions::kStarts, 1, false},
      {"calibrate", "calibrate " + kCyl, "--design-points", fit::FitOptions::kDesignPoints, 1,
       false},
      {"calibrate", "calibrate " + kCyl, "--threshold-scale", fit::FitOptions::kThresholdScale,
       1e-7, false},
      {"compare", "compare " + kCyl, "--repeats", AssessOptions::kRepeats},
      {"compare", "compare " + kCyl, "--orientations", fit::FitOptions::kMarginalPoints, 1, false},
      {"design", design, "--orientations", fit::FitOptions::kMarginalPoints, 1, false},
      {"diagnose", "diagnose " + kCyl, "--alpha", DiagnoseOptions::kAlpha, 1, false},
      {"diagnose", "diagnose " + kCyl, "--screen", DiagnoseOptions::kScreen},
      {"ladder", "ladder " + kCyl + " --add rate_restitution", "--repeats",
       AssessOptions::kRepeats},
      {"report", report, "--rounds", ReportOptions::kRounds, 1, false},
      {"report", report, "--alpha", DiagnoseOptions::kAlpha, 1, false},
      {"transfer fit", "transfer fit " + kCyl, "--replicates", transfer::FitSampling::kReplicates},
  };
  for (const RangedOption& o : options) {
    const double below = o.range.lo_open ? o.range.lo : o.range.lo - o.step;
    if (below >= 0 || !o.unsigned_) expect_refused(o, below);
    expect_refused(o, o.range.hi_open ? o.range.hi : o.range.hi + o.step);
    const test::RunResult help = ricochet(o.help + " --help");
    ASSERT_EQ(help.status, 0) << o.help;
    EXPECT_NE(help.out.find("in " + o.range.text()), std::string::npos)
        << o.help << " --help does not show " << o.option << " in " << o.range.text() << "\n"
        << help.out;
  }
}

}  // namespace
}  // namespace ricochet
