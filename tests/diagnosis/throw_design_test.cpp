// The design of throws (diagnosis/discrimination.hpp, throw_design.hpp): the T-criterion and its
// power against closed forms, the max-min selection on toy terms, and on a synthetic set whose
// truth has a speed-dependent restitution: the plan beats as many uniform throws, puts its
// throws where the rivals differ (fast impacts), and is the same bit for bit on a second run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "common/error.hpp"
#include "diagnosis/discrimination.hpp"
#include "diagnosis/synth.hpp"
#include "diagnosis/throw_design.hpp"

namespace ricochet::diagnosis {
namespace {

// --- the criterion ---

TEST(Discrimination, LambdaIsTheResidualOfTheLinearisedRefit) {
  // One state, two observables, one refit direction along the first: the second component of
  // the difference is what the refit cannot absorb.
  Eigen::VectorXd r(2);
  r << 3.0, 4.0;
  Eigen::MatrixXd G(2, 1);
  G << 2.0, 0.0;
  TermSum s(1);
  s.add(state_terms(r, G));
  EXPECT_NEAR(s.lambda(), 16.0, 1e-9);
  // No refit direction: the whole difference.
  TermSum none(0);
  none.add(state_terms(r, Eigen::MatrixXd(2, 0)));
  EXPECT_NEAR(none.lambda(), 25.0, 1e-12);
  // A difference the refit reaches exactly: 0.
  TermSum in_span(1);
  Eigen::VectorXd q(2);
  q << 3.0, 0.0;
  in_span.add(state_terms(q, G));
  EXPECT_NEAR(in_span.lambda(), 0.0, 1e-9);
}

TEST(Discrimination, ANullRefitDirectionChangesNothing) {
  // A parameter that moves nothing (mu in a sticking contact) is no refit direction.
  Eigen::VectorXd r(2);
  r << 3.0, 4.0;
  Eigen::MatrixXd G(2, 2);
  G << 2.0, 0.0, 0.0, 0.0;
  TermSum s(2);
  s.add(state_terms(r, G));
  EXPECT_NEAR(s.lambda(), 16.0, 1e-6);
}

TEST(Discrimination, PowerOfTheNoncentralChiSquareWithOneDegree) {
  EXPECT_NEAR(discrimination_power(0.0, 0.05), 0.05, 1e-9);  // the level itself
  // (1.96 + 0.8416)^2 = 7.849: the textbook 80 % power of a two-sided 5 % test.
  EXPECT_NEAR(discrimination_power(7.849, 0.05), 0.80, 2e-3);
  EXPECT_GT(discrimination_power(40.0, 0.05), 0.999);
  EXPECT_LT(discrimination_power(1.0, 0.01), discrimination_power(1.0, 0.05));
}

// Toy terms: direction 0 gains c_k at candidate k, direction 1 gains d_k; no refit parameters.
std::vector<Direction> toy(const std::vector<double>& c, const std::vector<double>& d) {
  std::vector<Direction> dirs(2);
  for (std::size_t k = 0; k < c.size(); ++k) {
    StateTerms a, b;
    a.c = c[k];
    b.c = d[k];
    dirs[0].states.push_back(a);
    dirs[1].states.push_back(b);
  }
  return dirs;
}

TEST(Discrimination, MaxMinBalancesThePairs) {
  // Candidates 0-1 serve pair 0 only, 2-3 pair 1 only, 4 both a little: with a budget of 2 the
  // max-min design takes one of each kind, not the two largest of one.
  const auto dirs = toy({10, 9, 0, 0, 1}, {0, 0, 8, 7, 1});
  const std::vector<PairRule> pairs = {{{0}}, {{1}}};
  SelectionOptions o;
  o.budget = 2;
  o.max_passes = 10;
  const Selection s = select_max_min(dirs, pairs, 0, 5, o);
  ASSERT_EQ(s.chosen.size(), 2u);
  std::vector<std::size_t> chosen = s.chosen;
  std::sort(chosen.begin(), chosen.end());
  EXPECT_EQ(chosen, (std::vector<std::size_t>{0, 2}));
  EXPECT_DOUBLE_EQ(s.value, 8.0);
}

TEST(Discrimination, ExchangeRepairsAGreedyStart) {
  // Greedy takes the balanced candidate 4 first (5 > 0 for any single other), then the best
  // partner; exchanging 4 for a specialist of the other pair does better.
  const auto dirs = toy({10, 0, 5}, {0, 10, 5});
  const std::vector<PairRule> pairs = {{{0}}, {{1}}};
  SelectionOptions o;
  o.budget = 2;
  o.max_passes = 10;
  const Selection s = select_max_min(dirs, pairs, 0, 3, o);
  EXPECT_DOUBLE_EQ(s.greedy_value, 5.0);
  EXPECT_DOUBLE_EQ(s.value, 10.0);
  EXPECT_GE(s.swaps, 1u);
}

// --- on synthetic sets whose truth has a speed-dependent restitution ---

// The wide box of the synthetic design: V_in^x 1.5-6 m/s, V_in^y -5 to -1 m/s, omega -90-0 rad/s.
WideBox wide_box() {
  return SynthOptions{}.wide;
}

// A truth with a speed-dependent restitution (e_n^2 halves between 0.8 and 3.3 m/s of approach
// speed), thrown over `design`: the lab's narrow incident states, or the wide box.
ImpactSet synthetic(Design design) {
  Model truth = Model::paper().with_effect("rate_restitution");
  truth.set("kv", 0.2);
  SynthOptions o;
  o.n = 24;
  o.seed = 5;
  o.design = design;
  o.incident = read_impact_set(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
  o.write_penetration = o.write_contact_duration = false;  // like the lab: velocities only
  return synthesize(truth, Shape::cylinder(), o).set;
}

const ImpactSet& lab_like() {
  static const ImpactSet s = synthetic(Design::kLab);
  return s;
}
const ImpactSet& wide() {
  static const ImpactSet s = synthetic(Design::kWide);
  return s;
}

DesignOptions small(std::size_t budget) {
  DesignOptions o;
  o.budget = budget;
  o.candidates = 256;
  o.seed = 3;
  return o;
}

const ThrowDesign& rate_vs_none(const ImpactSet& set) {
  static std::map<const ImpactSet*, ThrowDesign> done;
  auto it = done.find(&set);
  if (it == done.end())
    it = done.emplace(&set, design_throws(Model::paper(), Shape::cylinder(), set,
                                          {{}, {"rate_restitution"}}, wide_box(), small(12)))
             .first;
  return it->second;
}

double mean_abs_vin_y(const std::vector<Vel3>& states) {
  double m = 0;
  for (const Vel3& v : states) m += std::fabs(v[kVy]) / static_cast<double>(states.size());
  return m;
}

TEST(ThrowDesign, ThePlanBeatsAsManyUniformThrows) {
  const ThrowDesign d =
      design_throws(Model::paper(), Shape::cylinder(), lab_like(),
                    {{}, {"rate_restitution"}, {"inertial_drag"}}, wide_box(), small(12));
  ASSERT_EQ(d.plan.size(), 12u);
  ASSERT_EQ(d.uniform.size(), 12u);
  ASSERT_TRUE(std::isfinite(d.min_plan.lambda));
  EXPECT_GT(d.min_plan.lambda, d.min_uniform.lambda);
  EXPECT_GE(d.min_plan.power, d.min_uniform.power);
  EXPECT_GT(d.min_plan.lambda, d.min_set.lambda);  // new throws add information
  for (const auto& p : d.pairs) {
    if (!p.indistinguishable && !p.beyond_budget) {
      EXPECT_GE(p.plan.lambda, d.min_plan.lambda);
    }
  }
  // The same on the wide set, whose releases already span the box.
  const ThrowDesign& w = rate_vs_none(wide());
  EXPECT_GT(w.min_plan.lambda, w.min_uniform.lambda);
}

// The power is that of the diagnosis's second stage: each pair at alpha / (4 m (m - 1)) for m
// rivals other than `none`; a pair whose own greedy plan stays below 0.5 at that level is beyond
// the budget and leaves the criterion (throw_design.hpp).
TEST(ThrowDesign, PowerAtTheSecondStagesLevelAndPairsBeyondTheBudget) {
  const ThrowDesign d =
      design_throws(Model::paper(), Shape::cylinder(), lab_like(),
                    {{}, {"rate_restitution"}, {"inertial_drag"}}, wide_box(), small(12));
  EXPECT_DOUBLE_EQ(d.test_level, 0.05 / (4.0 * 2.0));  // m = 2 laws besides none, 2 per family
  for (const auto& p : d.pairs) {
    if (p.indistinguishable) continue;
    EXPECT_EQ(p.beyond_budget, p.alone.power < DesignOptions{}.budget_power);
    EXPECT_DOUBLE_EQ(p.alone.power, discrimination_power(p.alone.lambda, d.test_level));
    EXPECT_DOUBLE_EQ(p.plan.power, discrimination_power(p.plan.lambda, d.test_level));
  }
  // One throw decides rate_restitution against none on the lab-like set with power 0.96 at
  // this level: within the default budget power (0.5), beyond a required 0.99, and with
  // nothing left to decide the plan then has no weakest pair.
  DesignOptions one = small(1);
  const ThrowDesign within = design_throws(Model::paper(), Shape::cylinder(), lab_like(),
                                           {{}, {"rate_restitution"}}, wide_box(), one);
  ASSERT_EQ(within.pairs.size(), 1u);
  const double alone = within.pairs[0].alone.power;
  ASSERT_GT(alone, 0.5);
  ASSERT_LT(alone, 0.99);
  EXPECT_FALSE(within.pairs[0].beyond_budget);
  EXPECT_TRUE(std::isfinite(within.min_plan.lambda));
  one.budget_power = 0.99;
  const ThrowDesign beyond = design_throws(Model::paper(), Shape::cylinder(), lab_like(),
                                           {{}, {"rate_restitution"}}, wide_box(), one);
  EXPECT_TRUE(beyond.pairs[0].beyond_budget);
  EXPECT_TRUE(std::isnan(beyond.min_plan.lambda));
  EXPECT_EQ(beyond.plan.size(), 1u);  // still a plan: the space-filling fallback
}

TEST(ThrowDesign, ThrowsGoWhereTheRivalsDiffer) {
  // rate_restitution lowers e_n^2 with the approach speed. Calibrated on the lab's narrow
  // incident states (|V_in^y| 1.9-2.7 m/s), it and the constant law agree there and part in
  // faster impacts: the plan's mean |V_in^y| lies above the box centre (3 m/s).
  const ThrowDesign& d = rate_vs_none(lab_like());
  ASSERT_EQ(d.rivals.size(), 2u);
  EXPECT_GT(d.rivals[1].model.value("kv"), 0.0) << d.rivals[1].law;
  ASSERT_EQ(d.pairs.size(), 1u);
  EXPECT_TRUE(d.pairs[0].nested);
  EXPECT_FALSE(d.pairs[0].indistinguishable);
  const double centre = 0.5 * std::fabs(d.box.vin_y[0] + d.box.vin_y[1]);
  EXPECT_GT(mean_abs_vin_y(d.plan), centre);
  for (const Vel3& v : d.plan) {
    EXPECT_GE(v[kVx], d.box.vin_x[0]);
    EXPECT_LE(v[kVx], d.box.vin_x[1]);
    EXPECT_GE(v[kVy], d.box.vin_y[0]);
    EXPECT_LE(v[kVy], d.box.vin_y[1]);
    EXPECT_GE(v[kW], d.box.win[0]);
    EXPECT_LE(v[kW], d.box.win[1]);
  }
  // Calibrated over the whole speed range, a concave law and a constant one part at both ends
  // of it: the plan's |V_in^y| lies farther from the centre than the uniform draw's.
  const ThrowDesign& w = rate_vs_none(wide());
  const auto spread = [&](const std::vector<Vel3>& states) {
    double m = 0;
    for (const Vel3& v : states)
      m += std::fabs(std::fabs(v[kVy]) - centre) / static_cast<double>(states.size());
    return m;
  };
  EXPECT_GT(spread(w.plan), spread(w.uniform));
}

TEST(ThrowDesign, SameInputsSamePlanBitForBit) {
  DesignOptions o = small(12);
  o.assess.fit.threads = 1;  // another thread count: the plan must not depend on it
  const ThrowDesign again = design_throws(Model::paper(), Shape::cylinder(), lab_like(),
                                          {{}, {"rate_restitution"}}, wide_box(), o);
  const ThrowDesign& d = rate_vs_none(lab_like());
  ASSERT_EQ(again.plan.size(), d.plan.size());
  for (std::size_t i = 0; i < d.plan.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(again.plan[i][k], d.plan[i][k]) << i;
  EXPECT_EQ(again.min_plan.lambda, d.min_plan.lambda);
  EXPECT_EQ(again.uniform, d.uniform);
}

TEST(ThrowDesign, RivalsAreCheckedAgainstTheRegistry) {
  const Model base = Model::paper();
  const auto& reg = EffectRegistry::global();
  const std::vector<std::string> ok = {"none", "rate_restitution", "inertial_drag+ploughing"};
  const auto parsed = parse_rivals(ok, base, reg);
  ASSERT_EQ(parsed.size(), 3u);
  EXPECT_TRUE(parsed[0].empty());
  EXPECT_EQ(parsed[2], (std::vector<std::string>{"inertial_drag", "ploughing"}));
  const auto message = [&](std::vector<std::string> names) {
    try {
      parse_rivals(names, base, reg);
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--rivals");
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string unknown = message({"none", "bogus"});
  EXPECT_NE(unknown.find("unknown rival 'bogus'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("rate_restitution"), std::string::npos) << unknown;  // lists the known
  EXPECT_NE(message({"none", "normal"}).find("already in the base model"), std::string::npos);
  EXPECT_NE(message({"none"}).find("at least two"), std::string::npos);
  EXPECT_NE(message({"a+b+c", "none"}).find("at most two"), std::string::npos);
  EXPECT_NE(message({"ploughing+inertial_drag", "inertial_drag+ploughing"}).find("twice"),
            std::string::npos);
}

}  // namespace
}  // namespace ricochet::diagnosis
