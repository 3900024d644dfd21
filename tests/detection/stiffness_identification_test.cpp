// The contact stiffness kn is calibrated when, and only when, the contact features (maximum
// penetration, contact duration) enter the error (fit::calibration_model, the one decision;
// docs/diagnosis.md, "Which stiffnesses the contact features identify"), and it is then
// recovered from sets of the independent simulator (truth_sim.hpp: another integrator, step,
// lever arm and end of contact) whose kn = 3e7 N/m is three times the engine's nominal 1e7.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "diagnosis/assess.hpp"
#include "effects/model.hpp"
#include "engine/shape.hpp"
#include "fit/fit.hpp"
#include "support/program_test.hpp"
#include "truth_sim.hpp"

namespace ricochet {
namespace {

std::vector<std::string> calibrated_names(const Model& m) {
  std::vector<std::string> out;
  for (std::size_t i : m.calibrated_indices()) out.emplace_back(m.spec(i).name);
  return out;
}

// A set of the independent simulator (its own numerics: kn = 3e7 N/m), lab design.
ImpactSet independent_set(std::size_t n, std::uint64_t seed, bool contact_features) {
  truth::SetOptions o;
  o.n = n;
  o.seed = seed;
  o.refit = false;
  o.contact_features = contact_features;
  o.lab_vin =
      truth::lab_cylinder_states(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
  return truth::make_set(o).set;
}

const std::vector<std::string> kPaper = {"en2", "mu", "muR"};
const std::vector<std::string> kWithKn = {"kn", "en2", "mu", "muR"};

TEST(StiffnessCalibration, KnJoinsTheCalibratedSetOnlyWithContactTerms) {
  const Model paper = Model::paper();
  ASSERT_EQ(calibrated_names(paper), kPaper);
  fit::ErrorOptions e;  // Eq. 7: velocities only
  EXPECT_EQ(calibrated_names(fit::calibration_model(paper, e)), kPaper);
  e.penetration = true;
  EXPECT_EQ(calibrated_names(fit::calibration_model(paper, e)), kWithKn);
  e.penetration = false;
  e.contact_duration = true;
  EXPECT_EQ(calibrated_names(fit::calibration_model(paper, e)), kWithKn);
  // Idempotent, and kt, kr stay fixed (not identified: docs/diagnosis.md).
  EXPECT_EQ(calibrated_names(fit::calibration_model(fit::calibration_model(paper, e), e)), kWithKn);
  // The stiffness is searched in log(kn) (bounds 1e5-1e9 N/m), the coefficients linearly.
  // A held kn stays out, contact terms or not: a law given with its values (Model::held).
  Model held = paper;
  held.set_held("kn", true);
  EXPECT_EQ(calibrated_names(fit::calibration_model(held, e)), kPaper);
  EXPECT_TRUE(fit::log_scaled(paper.lower(paper.index("kn")), paper.upper(paper.index("kn"))));
  EXPECT_FALSE(fit::log_scaled(paper.lower(paper.index("en2")), paper.upper(paper.index("en2"))));
}

TEST(StiffnessCalibration, VelocityOnlySetsKeepKnFixed) {
  const Model paper = Model::paper();
  const Shape shape = Shape::resolve("cylinder");
  const ImpactSet velocities = independent_set(12, 2, false);
  const ImpactSet features = independent_set(12, 2, true);
  const diagnosis::AssessOptions o;
  // The diagnosis's view (compare, diagnose, ladder): velocities only, or features turned off
  // (--no-features), leave the paper's calibrated set; features add kn.
  EXPECT_EQ(calibrated_names(diagnosis::calibration_model_for(paper, velocities, o)), kPaper);
  diagnosis::AssessOptions off = o;
  off.use_features = false;
  EXPECT_EQ(calibrated_names(diagnosis::calibration_model_for(paper, features, off)), kPaper);
  EXPECT_EQ(calibrated_names(diagnosis::calibration_model_for(paper, features, o)), kWithKn);
  // A set missing the features on one release does not use them.
  ImpactSet partial = features;
  partial.impacts.back().penetration.reset();
  partial.impacts.back().contact_duration.reset();
  EXPECT_EQ(calibrated_names(diagnosis::calibration_model_for(paper, partial, o)), kPaper);
  // The fit on velocities: kn stays exactly the paper's.
  fit::FitOptions fo;
  fo.intervals = false;
  fo.starts = 2;
  fo.error = fit::with_contact_terms(fo.error, velocities);
  const fit::PopulationFit p = fit::calibrate_population(paper, shape, velocities, fo);
  EXPECT_EQ(p.calibrated, paper.calibrated_indices());
  EXPECT_EQ(p.params[paper.index("kn")], 1e7);
}

// (a) With features, kn is calibrated and recovered from a set whose kn is 3 x the nominal: a
// fixed kn (1e7 N/m) fails by a factor of three.
TEST(StiffnessCalibration, KnRecoveredFromAnIndependentSet) {
  const Model paper = Model::paper();
  const Shape shape = Shape::resolve("cylinder");
  const double kn_true = truth::Numerics{}.kn;  // 3e7 N/m
  ASSERT_NEAR(kn_true / paper.value("kn"), 3.0, 1e-12);
  const ImpactSet set = independent_set(40, 1, true);
  // The fit options of compare, diagnose and ladder on this set (set-mean error floors).
  fit::FitOptions fo =
      diagnosis::fit_options_for(set, diagnosis::resolve_scale(set, diagnosis::AssessOptions{}));
  ASSERT_TRUE(fo.error.penetration && fo.error.contact_duration);
  // One constant denominator per contact term: the set's mean penetration and duration.
  EXPECT_GT(fo.error.penetration_scale_m, 0.0);
  EXPECT_GT(fo.error.contact_duration_scale_s, 0.0);
  fo.interval_resolution = 0.005;
  const fit::PopulationFit p = fit::calibrate_population(paper, shape, set, fo);
  const double kn = p.params[paper.index("kn")];
  // Tolerance 12 %: over seeds 1-5 the study (stiffness_study) found 2.68-3.41e7 N/m, mean
  // 3.11e7 +- 0.27e7 (sd); this set (seed 1) 3.28e7 (+9 %). With the per-release
  // denominators max(measured, set mean), which weight down the releases whose 0.5 mm
  // penetration noise went up, the same set gave 3.62e7 (+21 %; mean +18 % over the seeds),
  // checked below. A fixed kn is 1e7.
  EXPECT_NEAR(kn / kn_true, 1.0, 0.12) << "kn = " << kn << " N/m";
  fit::FitOptions per_release = fo;
  per_release.error.penetration_scale_m = per_release.error.contact_duration_scale_s = 0;
  per_release.intervals = false;
  const double kn_per_release =
      fit::calibrate_population(paper, shape, set, per_release).params[paper.index("kn")];
  EXPECT_GT(kn_per_release / kn_true, 1.12) << "kn = " << kn_per_release << " N/m";
  RecordProperty("kn_N_per_m", std::to_string(kn));
  RecordProperty("kn_per_release_denominators_N_per_m", std::to_string(kn_per_release));
  const fit::ParameterInterval* iv = nullptr;
  for (const auto& i : p.intervals)
    if (i.name == "kn") iv = &i;
  ASSERT_NE(iv, nullptr);
  EXPECT_EQ(iv->status, fit::Identifiability::kIdentified) << iv->statement;
  EXPECT_LT(iv->hi / iv->lo, 1.5) << "[" << iv->lo << ", " << iv->hi << "] N/m";
  EXPECT_GT(iv->lo, paper.value("kn"));  // the nominal kn is excluded
}

// (c) The CLI: `ricochet calibrate` calibrates kn on a set with the features, keeps it fixed
// with --no-features.
class StiffnessCli : public test::ProgramTest {};

TEST_F(StiffnessCli, CalibrateFitsKnOnlyWithTheFeatures) {
  const std::string csv = (dir_ / "set.csv").string();
  const std::string make = test::quote(RICOCHET_TRUTH_EXE) +
                           " --n 4 --seed 3 --no-refit --contact-features --out " +
                           test::quote(csv) + " > /dev/null";
  ASSERT_EQ(std::system(make.c_str()), 0);
  const std::string args = "calibrate " + test::quote(csv) +
                           " --shape cylinder --starts 2 --no-intervals --threads 2 --json";
  const test::RunResult with = ricochet(args);
  ASSERT_EQ(with.status, 0) << with.err;
  const auto a = nlohmann::json::parse(with.out);
  EXPECT_TRUE(a["settings"]["error_penetration"].get<bool>());
  for (const auto& r : a["releases"]) {
    EXPECT_TRUE(r["params"].contains("kn")) << r.dump();
    EXPECT_FALSE(r["params"].contains("kt"));
  }
  const test::RunResult without = ricochet(args + " --no-features");
  ASSERT_EQ(without.status, 0) << without.err;
  const auto b = nlohmann::json::parse(without.out);
  EXPECT_FALSE(b["settings"]["error_penetration"].get<bool>());
  for (const auto& r : b["releases"]) {
    EXPECT_FALSE(r["params"].contains("kn"));
    EXPECT_EQ(r["fixed"]["kn"].get<double>(), 1e7);
  }
}

}  // namespace
}  // namespace ricochet
