// The diagnosis's options are checked once, by their problems() (common/option_problems.hpp):
// the defaults have none, an out-of-range value is a problem naming its field and range, and
// the functions that consume the options refuse them at their entry. The number of folds is
// resolved in one place (AssessOptions::folds_for), and the lab's noise is written in one place
// (fit/lab_noise.hpp).
#include <gtest/gtest.h>

#include <string>

#include "common/error.hpp"
#include "diagnosis/diagnose.hpp"
#include "diagnosis/inputs.hpp"
#include "diagnosis/synth.hpp"
#include "diagnosis/validation_report.hpp"
#include "fit/lab_noise.hpp"

namespace ricochet::diagnosis {
namespace {

// The problem of `problems` naming `option`, or nullptr.
const OptionProblem* find(const OptionProblems& problems, const std::string& option) {
  for (const auto& p : problems)
    if (p.option == option) return &p;
  return nullptr;
}

void expect_problem(const OptionProblems& problems, const std::string& option,
                    const std::string& says) {
  const OptionProblem* p = find(problems, option);
  ASSERT_NE(p, nullptr) << "no problem names " << option;
  EXPECT_NE(p->message.find(says), std::string::npos) << option << ": " << p->message;
}

TEST(DiagnosisOptions, DefaultsHaveNoProblem) {
  EXPECT_TRUE(AssessOptions{}.problems().empty());
  EXPECT_TRUE(DiagnoseOptions{}.problems().empty());
  EXPECT_TRUE(ReportOptions{}.problems().empty());
  // The command line's values, before any parse, too.
  EXPECT_TRUE(make_options(OptionValues{}).problems().empty());
}

TEST(DiagnosisOptions, OutOfRangeValuesAreProblemsNamingTheOption) {
  AssessOptions a;
  a.repeats = 21;
  expect_problem(a.problems(), "repeats", "value 21 is outside [1, 20]");
  a = {};
  a.repeats = 0;
  expect_problem(a.problems(), "repeats", "outside [1, 20]");
  a = {};
  a.folds = 1;
  expect_problem(a.problems(), "folds", "below 2");
  a = {};
  a.fit.alpha.marginal_points = 1;  // the nested fit options are prefixed
  expect_problem(a.problems(), "fit.alpha.marginal_points", "outside [2, 3600]");
  a = {};
  a.population_starts = 0;
  expect_problem(a.problems(), "population_starts", "outside [1, 1000]");

  DiagnoseOptions d;
  d.alpha = 1;
  expect_problem(d.problems(), "alpha", "value 1 is outside (0, 1)");
  d = {};
  d.alpha = 0;
  expect_problem(d.problems(), "alpha", "outside (0, 1)");
  d = {};
  d.screen = 1001;
  expect_problem(d.problems(), "screen", "outside [0, 1000]");
  d = {};
  d.assess.repeats = 50;
  expect_problem(d.problems(), "assess.repeats", "outside [1, 20]");

  ReportOptions r;
  r.rounds = 21;
  expect_problem(r.problems(), "rounds", "outside [0, 20]");
  r = {};
  r.diagnose.alpha = 2;
  expect_problem(r.problems(), "diagnose.alpha", "outside (0, 1)");
}

TEST(DiagnosisOptions, RangeBoundsThemselvesAreValid) {
  DiagnoseOptions d;
  d.assess.repeats = 20;
  d.screen = 1000;
  d.alpha = 0.5;
  d.assess.fit.alpha.marginal_points = 2;
  d.assess.folds = AssessOptions::kLeaveOneOut;
  EXPECT_TRUE(d.problems().empty());
  d.screen = 0;
  d.assess.repeats = 1;
  d.assess.folds = 2;
  EXPECT_TRUE(d.problems().empty());
}

TEST(DiagnosisOptions, TheConsumersRefuseBadOptionsAtTheirEntry) {
  // Refused before any work, even on an empty set: the options come first.
  const ImpactSet none;
  AssessOptions a;
  a.repeats = 0;
  try {
    (void)assess(Model::paper(), Shape::cylinder(), none, a);
    ADD_FAILURE() << "assess accepted repeats = 0";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "repeats");
    EXPECT_NE(e.detail().find("outside [1, 20]"), std::string::npos) << e.what();
  }
  DiagnoseOptions d;
  d.alpha = 1.5;
  try {
    (void)diagnose(Model::paper(), Shape::cylinder(), none, d);
    ADD_FAILURE() << "diagnose accepted alpha = 1.5";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "alpha");
  }
  ReportOptions r;
  r.rounds = -1;
  EXPECT_THROW((void)analyse({}, Model::paper(), r), InputError);
}

TEST(DiagnosisOptions, FoldsAreParsedOnceAndResolvedOnce) {
  EXPECT_EQ(parse_folds("5"), 5u);
  EXPECT_EQ(parse_folds("loro"), AssessOptions::kLeaveOneOut);
  for (const std::string bad : {"", "x", "-3", "2.5", "5 "})
    EXPECT_THROW((void)parse_folds(bad), InputError) << "'" << bad << "'";
  // The text parses; its range is the options' (0 and 1 parse and are refused by problems()).
  AssessOptions a;
  a.folds = parse_folds("1");
  EXPECT_NE(find(a.problems(), "folds"), nullptr);
  // folds_for: k clamped to [2, n]; leave-one-out is n.
  a.folds = 5;
  EXPECT_EQ(a.folds_for(30), 5u);
  EXPECT_EQ(a.folds_for(4), 4u);
  a.folds = AssessOptions::kLeaveOneOut;
  EXPECT_EQ(a.folds_for(23), 23u);
  OptionValues loro;
  loro.folds = "loro";
  EXPECT_EQ(make_options(loro).assess.folds_for(7), 7u);
  EXPECT_EQ(make_options(OptionValues{}).assess.folds, AssessOptions{}.folds);
}

TEST(LabNoise, IsWrittenInOnePlace) {
  const NoiseSpec lab = NoiseSpec::lab();
  EXPECT_EQ(lab.vin, fit::LabNoise::vin);
  EXPECT_EQ(lab.vout, fit::LabNoise::vout);
  EXPECT_EQ(lab.penetration_m, fit::LabNoise::penetration_m);
  EXPECT_EQ(lab.contact_duration_s, fit::LabNoise::contact_duration_s);
  const AssessOptions a;
  EXPECT_EQ(a.sigma_vin, fit::LabNoise::vin);
  EXPECT_EQ(a.sigma_penetration_m, fit::LabNoise::penetration_m);
  EXPECT_EQ(a.sigma_contact_duration_s, fit::LabNoise::contact_duration_s);
  EXPECT_EQ(a.fit.sigma, fit::LabNoise::vout);
  EXPECT_EQ(fit::FitOptions{}.sigma_penetration_m, fit::LabNoise::penetration_m);
  EXPECT_EQ(fit::FitOptions{}.sigma_contact_duration_s, fit::LabNoise::contact_duration_s);
}

}  // namespace
}  // namespace ricochet::diagnosis
