// Errors, noise floor and adequacy (diagnosis/assess.hpp), trends (diagnosis/trends.hpp) and the
// HTML writer (report/html.hpp), on real engine runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "common/error.hpp"
#include "diagnosis/assess.hpp"
#include "diagnosis/signature.hpp"
#include "diagnosis/synth.hpp"
#include "diagnosis/trends.hpp"
#include "report/html.hpp"

namespace ricochet::diagnosis {
namespace {

ImpactSet synthetic(const Model& truth, std::size_t n, std::uint64_t seed, NoiseSpec noise) {
  SynthOptions o;
  o.n = n;
  o.seed = seed;
  o.design = Design::kWide;
  o.noise = noise;
  return synthesize(truth, Shape::cylinder(), o).set;
}

// The paper's law with the base parameters of the synthetic tests (en2 0.2, mu 0.4, muR 0.15).
Model base_truth() {
  Model truth = Model::paper();
  truth.set("en2", 0.2);
  truth.set("mu", 0.4);
  truth.set("muR", 0.15);
  return truth;
}

Model with_values_for_test(const Model& m, const std::vector<double>& v) {
  Model out = m;
  out.set_values(v);
  return out;
}

AssessOptions fast() {
  AssessOptions o;
  o.folds = 4;
  return o;
}

TEST(Assess, ExactDataOfTheTrueModelHaveNoError) {
  const Model truth = base_truth();
  const ImpactSet set = synthetic(truth, 10, 3, NoiseSpec::none());
  const AssessOptions o = fast();
  const auto use = observables_of(set, o);
  EXPECT_TRUE(use[kObsPenetration] && use[kObsDuration]);
  const auto pred = predict_observables(truth, Shape::cylinder(), truth.values(), set, o);
  const ErrorReport r = error_report(set, pred, use, o);
  EXPECT_LT(r.error.mean, 1e-20);
  // Any other parameter value has an error.
  std::vector<double> p = truth.values();
  p[truth.index("en2")] = 0.3;
  const auto pred2 = predict_observables(truth, Shape::cylinder(), p, set, o);
  EXPECT_GT(error_report(set, pred2, use, o).term_mean[kObsVy], 1e-3);
}

TEST(Assess, DeclaredNoiseFloorMatchesTheErrorOfTheTruth) {
  // Noise on V_out only: the floor is sum_k sigma_k^2 / d_k^2 and the error of the truth
  // averages to it.
  Model truth = Model::paper();
  NoiseSpec noise;
  noise.vout = {0.1, 0.1, 3.4};
  const ImpactSet set = synthetic(truth, 120, 5, noise);
  AssessOptions o = fast();
  o.use_features = false;
  const auto use = observables_of(set, o);
  const NoiseFloor f = noise_floor(truth, Shape::cylinder(), truth.values(), set, use, o);
  EXPECT_EQ(f.source, "declared");
  const auto pred = predict_observables(truth, Shape::cylinder(), truth.values(), set, o);
  const ErrorReport r = error_report(set, pred, use, o);
  EXPECT_NEAR(r.error.mean, f.value.mean, 3 * r.error.se) << "floor " << f.value.mean;
  EXPECT_GT(f.value.mean, 0);
}

TEST(Assess, TableOneScaleWhenNothingIsDeclaredAndVinNoiseIsPropagated) {
  ImpactSet lab = lab_incident_states(Shape::cylinder());
  AssessOptions o = fast();
  const auto use = observables_of(lab, o);
  EXPECT_FALSE(use[kObsPenetration]);
  const Model m = Model::paper();
  const NoiseFloor f = noise_floor(m, Shape::cylinder(), m.values(), lab, use, o);
  EXPECT_EQ(f.source, "table1");
  // Without V_in noise the floor is smaller: the propagated part is there.
  AssessOptions quiet = o;
  quiet.sigma_vin = {0, 0, 0};
  const NoiseFloor g = noise_floor(m, Shape::cylinder(), m.values(), lab, use, quiet);
  EXPECT_LT(g.value.mean, f.value.mean);
  EXPECT_GT(f.nearest_neighbour, 0);
}

// Two groups of replicate releases whose outputs differ only in V_out^y (by `spread`); release r
// of group g has V_in^x = 3 + g + vin_jitter * r (the jitter mimics reconstructed V_in).
ImpactSet replicate_groups(const std::vector<double>& spread, double vin_jitter) {
  ImpactSet set;
  set.source = "replicates";
  for (int g = 0; g < 2; ++g)
    for (std::size_t r = 0; r < spread.size(); ++r) {
      Impact im;
      im.id = "R" + std::to_string(g) + std::to_string(r);
      im.shape = "cylinder";
      im.vin = {3.0 + g + vin_jitter * static_cast<double>(r), -2.3, -60.0};
      im.vout = {3.0, 1.0 + spread[r], -40.0};
      set.impacts.push_back(im);
    }
  return set;
}

// The floor expected from a pooled V_out^y variance `var` (Eq. 7 denominators |V_out^y|).
double pooled_floor(const ImpactSet& set, double var) {
  double expected = 0;
  for (const auto& im : set.impacts)
    expected += var / (im.vout[1] * im.vout[1]) / static_cast<double>(set.size());
  return expected;
}

NoiseFloor floor_of(const ImpactSet& set) {
  AssessOptions o = fast();
  o.scale = ErrorScale::kEq7;
  const Model m = Model::paper();
  return noise_floor(m, Shape::cylinder(), m.values(), set, observables_of(set, o), o);
}

TEST(Assess, ReplicatesGiveThePooledVariance) {
  // Two groups of identical incident states, outputs with a known spread in V_out^y only.
  const ImpactSet set = replicate_groups({-0.1, 0.1, -0.1, 0.1}, 0.0);
  const NoiseFloor f = floor_of(set);
  EXPECT_EQ(f.source, "replicates");
  EXPECT_EQ(f.replicate_groups, 2u);
  // Pooled variance of V_out^y: 8 * 0.01 / (8 - 2); denominator |V_out^y| = 0.9 or 1.1.
  EXPECT_NEAR(f.value.mean, pooled_floor(set, 8 * 0.01 / 6.0), 1e-12);
  EXPECT_EQ(f.term_mean[kObsVx], 0.0);
}

// A resolved campaign's replicas (other bed, other position) reconstruct slightly different
// V_in from the same nominal state: the replicate label groups them, exact V_in equality cannot.
TEST(Assess, ReplicateLabelsGroupReleasesWhoseMeasuredVinDiffers) {
  ImpactSet set = replicate_groups({-0.1, 0.0, 0.1}, 0.01);
  for (auto& im : set.impacts) im.sigma_vout = Vel3{1e-6, 1e-6, 1e-5};  // clean-track errors
  // Without labels: no two V_in are equal, the declared (tiny) sigmas make the floor.
  const NoiseFloor declared = floor_of(set);
  EXPECT_EQ(declared.source, "declared");
  for (auto& im : set.impacts) im.replicate = "g" + im.id.substr(1, 1);
  const NoiseFloor f = floor_of(set);
  EXPECT_EQ(f.source, "replicates");
  EXPECT_EQ(f.replicate_groups, 2u);
  // Pooled V_out^y variance: 6 releases in 2 groups, 4 * 0.01 / (6 - 2).
  EXPECT_NEAR(f.value.mean, pooled_floor(set, 4 * 0.01 / 4.0), 1e-12);
  EXPECT_GT(f.value.mean, 2.0 * declared.value.mean);
}

// A set without replicates borrows the pooled scatter of another set's replicates on the same
// ground (--floor-replicates): its floor is then the one it would have with that scatter, and a
// set with replicates of its own keeps its own.
TEST(Assess, ASetWithoutReplicatesBorrowsAnotherSetsPooledScatter) {
  const ImpactSet replicated = replicate_groups({-0.1, 0.1, -0.1, 0.1}, 0.0);
  ReplicateScatter b;
  b.groups = 2;
  b.dof = 6;
  b.source = "other.h5";
  b.variance = {0.0, 8 * 0.01 / 6.0, 0.0, NAN, NAN};                // by hand, as in the test above
  ImpactSet single = replicate_groups({0.0, 0.2, 0.4, 0.6}, 0.01);  // no two V_in equal
  for (auto& im : single.impacts) im.sigma_vout = Vel3{1e-6, 1e-6, 1e-5};
  AssessOptions o = fast();
  o.scale = ErrorScale::kEq7;
  o.borrowed_floor = b;
  const Model m = Model::paper();
  const NoiseFloor f =
      noise_floor(m, Shape::cylinder(), m.values(), single, observables_of(single, o), o);
  EXPECT_EQ(f.source, "borrowed replicates");
  EXPECT_NE(f.description.find("other.h5"), std::string::npos) << f.description;
  EXPECT_NEAR(f.value.mean, pooled_floor(single, 8 * 0.01 / 6.0), 1e-12);
  // Its own replicates win over borrowed ones.
  const NoiseFloor own =
      noise_floor(m, Shape::cylinder(), m.values(), replicated, observables_of(replicated, o), o);
  EXPECT_EQ(own.source, "replicates");
  // A scatter without an observable the error uses is refused, naming the file and the field.
  ImpactSet with_depth = single;
  with_depth.extra_names = {"penetration"};
  with_depth.extra_units = {"m"};
  for (auto& im : with_depth.impacts) im.extra = {0.004};
  try {
    noise_floor(m, Shape::cylinder(), m.values(), with_depth, {true, true, true, true, false}, o);
    ADD_FAILURE() << "a borrowed floor without penetration was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "penetration");
    EXPECT_EQ(e.file(), "other.h5");
  }
}

TEST(Assess, SetMeanFloorsRaiseSmallDenominators) {
  ImpactSet lab = lab_incident_states(Shape::triangle());
  AssessOptions o;
  const AssessOptions r = resolve_scale(lab, o);
  // Mean |omega_out| of the 31 triangles (paper Table 2 mean -17.32 rad/s, all but one < 0).
  EXPECT_GT(r.fit.error.floor[2], 15.0);
  EXPECT_EQ(resolve_scale(lab, r).fit.error.floor[2], r.fit.error.floor[2]);  // idempotent
  o.scale = ErrorScale::kEq7;
  EXPECT_EQ(resolve_scale(lab, o).fit.error.floor[2], 1.0);
}

TEST(Assess, TheTrueModelIsAdequateAndAWrongOneIsNot) {
  const Model truth = base_truth();
  const ImpactSet set = synthetic(truth, 24, 11, NoiseSpec::lab());
  AssessOptions o = fast();
  const Assessment a = assess(truth, Shape::cylinder(), set, o);
  const NoiseFloor f = noise_floor(truth, Shape::cylinder(), a.population.params, set, a.use, o);
  const Adequacy q = adequacy(a, f);
  EXPECT_TRUE(q.adequate) << a.heldout.error.mean << " vs floor " << f.value.mean;
  EXPECT_LE(a.insample.error.mean, a.heldout.error.mean);
  // en2 recovered by the population fit within the noise.
  EXPECT_NEAR(a.population.params[truth.index("en2")], 0.2, 0.05);

  // Data from a very different law: the paper's law cannot be adequate.
  Model other = Model::paper().with_effect("rate_restitution");
  other.set("kv", 0.5);
  other.set("en2", 0.6);
  const ImpactSet set2 = synthetic(other, 24, 11, NoiseSpec::lab());
  const Assessment b = assess(truth, Shape::cylinder(), set2, o);
  const NoiseFloor g = noise_floor(truth, Shape::cylinder(), b.population.params, set2, b.use, o);
  EXPECT_FALSE(adequacy(b, g).adequate) << b.heldout.error.mean << " vs floor " << g.value.mean;
}

// The lab triangles' population objective is rough (rebound statuses and orientation cells
// switch with the parameters): the multi-start once stopped at 0.935 while every fold fit found
// parameters fitting the whole set better (0.827 against 0.935). On the full set, no fold's
// optimum may now beat the full-set optimum by more than 0.5 % (the redone folds still find
// points 0.07 % better: a rough objective has no exact optimum), and the in-sample error may
// not exceed the held-out error.
TEST(Assess, TheFullSetOptimumBeatsEveryFoldOptimumOnTheLabTriangles) {
  const ImpactSet set =
      read_impact_set(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/triangles.csv");
  const Shape shape = Shape::triangle();
  const AssessOptions o = resolve_scale(set, AssessOptions{});
  const Assessment a = assess(Model::paper(), shape, set, o);
  const fit::FitOptions fo = fit_options_for(set, o);
  ASSERT_EQ(a.fold_params.size(), a.cv.splits());
  ASSERT_EQ(a.cv.splits(), a.folds * a.cv.repeats);
  for (const auto& p : a.fold_params) {
    const auto pred = predict_observables(Model::paper(), shape, p, set, o);
    EXPECT_GE(error_report(set, pred, a.use, o).error.mean, 0.995 * a.insample.error.mean);
  }
  EXPECT_LE(a.insample.error.mean, a.heldout.error.mean);
}

// The held-out prediction of a release never sees the release (issue 10): change its measured
// outputs wildly and its held-out prediction must not move, bit for bit, for the base model and
// for a candidate warm-started from it. (Before the leak-free folds, changing one release's
// V_out moved its own "held-out" prediction by 0.21 m/s and 5.1 rad/s.)
// The leak tests' set (16 wide-design releases of the base truth) and the same set with the
// victim's measured outputs moved wildly.
constexpr std::size_t kVictim = 5;
std::pair<ImpactSet, ImpactSet> victim_sets() {
  SynthOptions so;
  so.n = 16;
  so.seed = 21;
  so.design = Design::kWide;
  so.write_penetration = so.write_contact_duration = false;
  const ImpactSet set = synthesize(base_truth(), Shape::cylinder(), so).set;
  ImpactSet moved = set;
  moved.impacts[kVictim].vout = {9.0, 4.0, 150.0};
  return {set, moved};
}

TEST(Assess, AHeldOutPredictionIgnoresItsOwnMeasuredOutputs) {
  const auto [set, moved] = victim_sets();
  const std::size_t victim = kVictim;
  AssessOptions o;
  o.folds = 4;
  o.repeats = 2;
  const Model base = Model::paper();
  const Assessment a = assess(base, Shape::cylinder(), set, o);
  const Assessment b = assess(base, Shape::cylinder(), moved, o);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(a.heldout_predictions[victim].value[k], b.heldout_predictions[victim].value[k])
        << "component " << k;
  // The full-set fit does see it (the test can fail: the change is not ignored everywhere).
  EXPECT_NE(a.population.params, b.population.params);
  // A candidate warm-started split by split from the base model's fold optima.
  const Model cand_a =
      with_values_for_test(base, a.population.params).with_effect("rate_restitution", true);
  const Model cand_b =
      with_values_for_test(base, b.population.params).with_effect("rate_restitution", true);
  const Assessment ca = assess(cand_a, Shape::cylinder(), set, o, &a);
  const Assessment cb = assess(cand_b, Shape::cylinder(), moved, o, &b);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(ca.heldout_predictions[victim].value[k], cb.heldout_predictions[victim].value[k])
        << "component " << k;
}

// The same, through a model whose values were fitted on the very set (`diagnose --model` with a
// model written from it, the next round of `ladder --auto`): a fold fit that started from those
// values would carry its held-out releases in through the start point (issue 31, 5a). The fold
// fits start from the declared nominal values instead, so the victim's held-out prediction does
// not move, and equals the one made from the paper's model.
TEST(Assess, AHeldOutPredictionIgnoresItsOutputsThroughAModelFittedOnTheSet) {
  const auto [set, moved] = victim_sets();
  const std::size_t victim = kVictim;
  AssessOptions o;
  o.folds = 4;
  o.repeats = 1;
  const Model base = Model::paper();
  const Assessment a = assess(base, Shape::cylinder(), set, o);
  const Assessment b = assess(base, Shape::cylinder(), moved, o);
  const Model fitted_a = with_values_for_test(base, a.population.params);
  const Model fitted_b = with_values_for_test(base, b.population.params);
  ASSERT_NE(fitted_a.values(), fitted_b.values());  // the start points differ
  const Assessment a2 = assess(fitted_a, Shape::cylinder(), set, o);
  const Assessment b2 = assess(fitted_b, Shape::cylinder(), moved, o);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(a2.heldout_predictions[victim].value[k], b2.heldout_predictions[victim].value[k])
        << "component " << k;
    EXPECT_EQ(a2.heldout_predictions[victim].value[k], a.heldout_predictions[victim].value[k])
        << "component " << k;
  }
  // Every fold starts from the nominal values, which no data chose.
  const Model start = nominal_start(fitted_a);
  for (std::size_t i : start.calibrated_indices())
    EXPECT_EQ(start.values()[i], start.spec(i).nominal) << start.spec(i).name;
}

// A split model (the ladder's force-law rung: a law discovered on each split's training
// histories) is made from the training releases alone: the maker below sets a fixed drag from
// the mean measured V_out^y of the releases it is given, so that a maker handed a test release
// would move the victim's prediction when the victim's outputs move. It is not handed one: the
// victim's held-out prediction is the same bit for bit, each split's model is kept, and the
// maker saw exactly each split's training releases.
TEST(Assess, ASplitModelIsMadeFromItsTrainingReleasesAlone) {
  const auto [set, moved] = victim_sets();
  AssessOptions o;
  o.folds = 4;
  o.repeats = 1;
  const Model base = Model::paper();
  auto maker = [&](const ImpactSet& s, std::vector<std::vector<std::size_t>>& seen) {
    return [&s, &seen, base](const std::vector<std::size_t>& train) {
      seen.push_back(train);
      double vy = 0;
      for (std::size_t i : train) vy += s.impacts[i].vout[kVy];
      Model m = base.with_effect("term_inertial_drag", /*at_neutral=*/true);
      m.set("c_inertial_drag", 20.0 * std::abs(vy) / static_cast<double>(train.size()));
      m.set_calibrated("c_inertial_drag", false);
      return m;
    };
  };
  std::vector<std::vector<std::size_t>> seen_a, seen_b;
  const Model full = base.with_effect("term_inertial_drag", true);
  const Assessment a = assess(full, Shape::cylinder(), set, o, maker(set, seen_a));
  const Assessment b = assess(full, Shape::cylinder(), moved, o, maker(moved, seen_b));
  ASSERT_EQ(a.fold_models.size(), a.cv.splits());
  ASSERT_EQ(seen_a.size(), a.cv.splits());
  for (std::size_t j = 0; j < a.cv.splits(); ++j) {
    EXPECT_EQ(seen_a[j], a.cv.train[j]);
    // The victim's outputs enter the drag of the splits that train on it, and only those.
    const bool trains_on_victim =
        std::find(a.cv.train[j].begin(), a.cv.train[j].end(), kVictim) != a.cv.train[j].end();
    const std::size_t d = a.fold_models[j].index("c_inertial_drag");
    EXPECT_EQ(a.fold_models[j].values()[d] != b.fold_models[j].values()[d], trains_on_victim);
    EXPECT_EQ(a.fold_params[j][d], a.fold_models[j].values()[d]);  // held, not calibrated
  }
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(a.heldout_predictions[kVictim].value[k], b.heldout_predictions[kVictim].value[k])
        << "component " << k;
}

TEST(Assess, CrossValidationDesignIsAPartitionPerRepeat) {
  const CvDesign cv = make_cv_design(23, 5, 3, 7);
  ASSERT_EQ(cv.splits(), 15u);
  for (std::size_t r = 0; r < 3; ++r) {
    std::vector<int> seen(23, 0);
    for (std::size_t f = 0; f < 5; ++f) {
      const auto& test = cv.test[r * 5 + f];
      EXPECT_GE(test.size(), 4u);
      EXPECT_LE(test.size(), 5u);
      EXPECT_EQ(test.size() + cv.train[r * 5 + f].size(), 23u);
      for (std::size_t i : test) ++seen[i];
    }
    for (int c : seen) EXPECT_EQ(c, 1);
  }
  // Two repeats are different partitions; the same seed gives the same design.
  EXPECT_NE(cv.test[0], cv.test[5]);
  EXPECT_EQ(make_cv_design(23, 5, 3, 7).test, cv.test);
  EXPECT_NE(make_cv_design(23, 5, 3, 8).test, cv.test);
  EXPECT_THROW(make_cv_design(3, 5, 1, 1), std::invalid_argument);
}

// Effect knowledge lives in the effects (issue 10): every registered effect says what it stands
// for, and every candidate (an effect outside the paper's law) which residuals or calibrated
// parameters it should move, against which features the diagnosis computes: its words parse
// (the registry refused any other), a parameter trend names a role the paper's law has, and
// every feature is one that impact_features() computes.
TEST(Signatures, EveryRegisteredEffectDeclaresOne) {
  const Model paper = Model::paper();
  ImpactSet set;
  Impact im;
  im.vin = {2.9, -2.3, -65.0};
  im.alpha_in = 0.1;
  im.penetration = 3e-3;
  im.contact_duration = 1e-2;
  set.impacts = {im, im};
  std::set<std::string> computed;
  for (const Feature& f : impact_features(set, {})) computed.insert(f.name);
  // The vocabulary and the features the diagnosis computes are the same words.
  EXPECT_EQ(computed.size(), kImpactFeatureCount);
  for (std::size_t i = 0; i < kImpactFeatureCount; ++i)
    EXPECT_TRUE(computed.count(std::string(feature_name(static_cast<ImpactFeature>(i)))));
  for (const Effect* e : EffectRegistry::global().all()) {
    const Signature s = e->signature();
    EXPECT_FALSE(s.meaning.empty()) << e->name();
    if (paper.has_effect(e->name())) continue;
    EXPECT_FALSE(s.trends.empty()) << e->name();
    for (const auto& t : s.trends) {
      const ExpectedTrend x = parse_trend(t);
      EXPECT_TRUE(computed.count(std::string(feature_name(x.feature))))
          << e->name() << ": " << t.feature;
      if (x.quantity != TrendQuantity::kParameter) continue;
      bool found = false;
      for (std::size_t j = 0; j < paper.parameter_count(); ++j)
        found = found || paper.spec(j).role == x.parameter;
      EXPECT_TRUE(found) << e->name() << ": " << t.quantity;
    }
  }
}

TEST(Trends, PearsonAndSpearmanMustAgree) {
  // One release far from the others in the feature and with an outlying residual (like lab
  // cylinder C12): Pearson alone calls a trend, the rank test does not. A clean monotone trend
  // passes both.
  Feature f{"speed_in", "|V_in| [m/s]", false, {}};
  ErrorReport r;
  for (int i = 0; i < 30; ++i) {
    f.values.push_back(i == 0 ? 0.0 : 10.0 + 0.1 * i);
    Obs res{};
    res[kObsVx] = i == 0 ? 5.0 : (i % 2 ? 0.1 : -0.1);  // no trend but the outlier
    res[kObsVy] = 0.01 * i;                             // clean trend
    r.residual.push_back(res);
  }
  const std::array<bool, kObservables> use{true, true, false, false, false};
  const auto t = residual_trends(r, use, {f});
  const Trend* vx = find_trend(t, "residual vx", "speed_in");
  const Trend* vy = find_trend(t, "residual vy", "speed_in");
  ASSERT_TRUE(vx && vy);
  EXPECT_LT(vx->p, 0.01);  // Pearson alone would call it
  EXPECT_GT(vx->p_rank, 0.01);
  EXPECT_FALSE(vx->significant);
  EXPECT_TRUE(vy->significant);
  EXPECT_NEAR(vy->rho, 1.0, 1e-12);
  EXPECT_NE(describe(*vy).find("grows with |V_in|"), std::string::npos);
}

TEST(Html, EscapeAndBase64) {
  EXPECT_EQ(report::html_escape("<a href=\"x\">&'</a>"),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;&lt;/a&gt;");
  // RFC 4648 test vectors.
  EXPECT_EQ(report::base64(""), "");
  EXPECT_EQ(report::base64("f"), "Zg==");
  EXPECT_EQ(report::base64("fo"), "Zm8=");
  EXPECT_EQ(report::base64("foo"), "Zm9v");
  EXPECT_EQ(report::base64("foob"), "Zm9vYg==");
  EXPECT_EQ(report::base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(report::base64("foobar"), "Zm9vYmFy");
}

TEST(Html, CompactSvgDropsOnlyEmptyGroups) {
  // An empty group, an empty group nested in one that becomes empty, a drawn group, a
  // self-closing group, an element whose name starts with "g", text.
  const std::string svg =
      "<svg>\n"
      "<g fill=\"none\" color=\"black\">\n</g>\n"
      "<g id=\"a\"><g stroke=\"gray\">\t\n</g></g>\n"
      "<g class=\"x\">\n\t<path d='M0,0 L1,1'/></g>\n"
      "<g/>\n"
      "<gradient id=\"q\"></gradient>\n"
      "<text> 3.2</text>\n"
      "</svg>";
  EXPECT_EQ(report::compact_svg(svg),
            "<svg>\n"
            "<g class=\"x\">\n\t<path d='M0,0 L1,1'/></g>\n"
            "<g/>\n"
            "<gradient id=\"q\"></gradient>\n"
            "<text> 3.2</text>\n"
            "</svg>");
  EXPECT_EQ(report::compact_svg(""), "");
  EXPECT_EQ(report::compact_svg("<g>"), "<g>");  // unterminated: kept as it is
}

TEST(Html, PageEmbedsFiguresAndEscapesText) {
  report::HtmlPage page("Title <1>");
  page.heading(2, "Section & more", "s1");
  page.paragraph("a < b");
  page.table({"x", "y [m]"}, {{"1.5", "text"}});
  report::Figure fig;
  report::Panel p;
  report::Series line;
  line.x = {0, 1};
  line.y = {0, 1};
  p.series.push_back(line);
  fig.panels = {p};
  fig.columns = 1;
  page.figure(fig, "a figure");
  EXPECT_EQ(page.figures(), 1u);
  const std::string html = page.html();
  EXPECT_NE(html.find("<title>Title &lt;1&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("a &lt; b"), std::string::npos);
  EXPECT_NE(html.find("src=\"data:image/svg+xml;base64,"), std::string::npos);
  EXPECT_NE(html.find("href=\"#s1\""), std::string::npos);
  EXPECT_NE(html.find("<td class=\"num\">1.5</td>"), std::string::npos);
  // Nothing is fetched from elsewhere (outside the embedded data).
  std::string outside = html;
  for (std::size_t k = outside.find("base64,"); k != std::string::npos;
       k = outside.find("base64,", k + 7))
    outside.erase(k + 7, outside.find('"', k) - (k + 7));
  EXPECT_EQ(outside.find("http"), std::string::npos);
  EXPECT_EQ(outside.find("src=\"/"), std::string::npos);
  EXPECT_THROW(page.figure_file("/nonexistent.svg", "x"), std::runtime_error);
}

// A supported candidate that the fit left at its neutral value adds nothing: auto_ladder stops on
// it instead of adding it (a resolved campaign's third rung, docs/diagnosis.md).
TEST(LeftNeutral, OnlyWhenEveryParameterOfTheEffectsSitsAtItsNeutralValue) {
  const EffectRegistry& reg = EffectRegistry::global();
  const Model m = Model::paper()
                      .with_effect("rate_restitution", true, reg)
                      .with_effect("kn_spin_linear", true, reg);
  std::vector<double> v = m.values();
  EXPECT_TRUE(detail::left_neutral(m, v, {"rate_restitution"}, reg));
  EXPECT_TRUE(detail::left_neutral(m, v, {"rate_restitution", "kn_spin_linear"}, reg));
  v[m.index("c_kn_spin")] = 0.01;
  EXPECT_TRUE(detail::left_neutral(m, v, {"rate_restitution"}, reg));
  EXPECT_FALSE(detail::left_neutral(m, v, {"kn_spin_linear"}, reg));
  EXPECT_FALSE(detail::left_neutral(m, v, {"rate_restitution", "kn_spin_linear"}, reg));
}

}  // namespace
}  // namespace ricochet::diagnosis
