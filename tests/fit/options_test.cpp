// The calibration's options are checked once, by FitOptions::problems() (common/
// option_problems.hpp): the defaults have none, an out-of-range value is a problem naming its
// field and range, and the calibrations refuse them at their entry.
#include <gtest/gtest.h>

#include <string>

#include "common/error.hpp"
#include "fit/fit.hpp"

namespace ricochet::fit {
namespace {

bool names(const OptionProblems& problems, const std::string& option, const std::string& says) {
  for (const auto& p : problems)
    if (p.option == option && p.message.find(says) != std::string::npos) return true;
  return false;
}

TEST(FitOptionsProblems, DefaultsHaveNoProblem) {
  EXPECT_TRUE(FitOptions{}.problems().empty());
  FitOptions f;
  f.design_points = -1;  // no design: the diagnosis's local refinements
  f.alpha.mode = AlphaMode::kMarginal;
  EXPECT_TRUE(f.problems().empty());
}

TEST(FitOptionsProblems, OutOfRangeValuesAreProblemsNamingTheOption) {
  const auto with = [](auto change) {
    FitOptions f;
    change(f);
    return f.problems();
  };
  EXPECT_TRUE(
      names(with([](FitOptions& f) { f.starts = 0; }), "starts", "value 0 is outside [1, 1000]"));
  EXPECT_TRUE(names(with([](FitOptions& f) { f.design_points = -2; }), "design_points",
                    "outside [-1, 1e+06]"));
  EXPECT_TRUE(names(with([](FitOptions& f) { f.threshold_scale = 0; }), "threshold_scale",
                    "outside [1e-06, 1e+06]"));
  EXPECT_TRUE(names(with([](FitOptions& f) { f.sigma[2] = -1; }), "sigma", "outside"));
  EXPECT_TRUE(names(with([](FitOptions& f) { f.alpha.marginal_points = 1; }),
                    "alpha.marginal_points", "outside [2, 3600]"));
  EXPECT_TRUE(names(with([](FitOptions& f) { f.alpha.min_rad = f.alpha.max_rad; }), "alpha.max_rad",
                    "above alpha.min_rad"));
  EXPECT_TRUE(names(with([](FitOptions& f) { f.xtol = 0; }), "xtol", "outside (0, 1)"));
}

TEST(FitOptionsProblems, TheCalibrationsRefuseBadOptionsAtTheirEntry) {
  FitOptions f;
  f.starts = 0;
  const ImpactSet none;
  try {
    (void)calibrate_population(Model::paper(), Shape::cylinder(), none, f);
    ADD_FAILURE() << "calibrate_population accepted starts = 0";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "starts");
  }
  EXPECT_THROW((void)calibrate_releases(Model::paper(), Shape::cylinder(), none, f), InputError);
  EXPECT_THROW((void)calibrate_release(Model::paper(), Shape::cylinder(), Impact{}, f), InputError);
}

}  // namespace
}  // namespace ricochet::fit
