// Paired comparison of two conditions of the same impacts (stats/paired.hpp): the pairing by id
// prefix, the differences in scale units, the Student t interval (checked against numbers worked
// by hand, not against the code) and the rule.
#include "stats/paired.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "common/error.hpp"

namespace ricochet::stats {
namespace {

Impact impact(const std::string& id, const std::string& shape, double vx, double vy, double w) {
  Impact im;
  im.id = id;
  im.shape = shape;
  im.vin = {2.9, -2.3, -65};
  im.vout = {vx, vy, w};
  return im;
}

const std::map<std::string, std::array<double, 3>> kScale = {{"cylinder", {0.5, 0.2, 10.0}},
                                                             {"triangle", {1.0, 0.25, 5.0}}};

// Four pairs, differences in scale units chosen by hand: V_out^x +0.2, +0.4, +0.6, +0.8 (mean
// 0.5, sd 0.2582); V_out^y 0 on every pair; omega_out -0.1 on every pair but one (-0.5).
ImpactSet four_pairs() {
  ImpactSet s;
  s.source = "four-pairs";
  const std::array<double, 4> dx = {0.2, 0.4, 0.6, 0.8};
  const std::array<double, 4> dw = {-0.1, -0.1, -0.1, -0.5};
  for (int i = 0; i < 4; ++i) {
    const std::string shape = i < 2 ? "cylinder" : "triangle";
    const auto& sc = kScale.at(shape);
    const std::string key = "k" + std::to_string(i);
    s.impacts.push_back(impact("A-" + key, shape, 3.0, 1.0, -40.0));
    s.impacts.push_back(impact("B-" + key, shape, 3.0 + dx[i] * sc[0], 1.0, -40.0 + dw[i] * sc[2]));
  }
  s.impacts.push_back(impact("A-lonely", "cylinder", 3.0, 1.0, -40.0));
  return s;
}

TEST(Paired, DifferencesIntervalsAndTheRuleMatchNumbersWorkedByHand) {
  const PairedComparison c = paired_comparison(four_pairs(), "A-", "B-", kScale);
  ASSERT_EQ(c.keys.size(), 4u);
  EXPECT_EQ(c.keys.front(), "k0");
  ASSERT_EQ(c.unpaired.size(), 1u);
  EXPECT_EQ(c.unpaired.front(), "A-lonely");
  // V_out^x: mean 0.5, sd sqrt(0.2/3) = 0.25820, t_{3, 0.975} = 3.18245: half-width 0.41085.
  const PairedComponent& x = c.components[0];
  EXPECT_NEAR(x.mean, 0.5, 1e-12);
  EXPECT_NEAR(x.sd, 0.2581989, 1e-6);
  EXPECT_NEAR(x.lo, 0.5 - 0.410848, 1e-5);
  EXPECT_NEAR(x.hi, 0.5 + 0.410848, 1e-5);
  EXPECT_FALSE(x.interval_holds_zero);
  EXPECT_FALSE(x.within_margin);
  EXPECT_FALSE(x.holds);
  // V_out^y: every difference 0: sd 0, interval [0, 0] holds 0.
  EXPECT_TRUE(c.components[1].holds);
  // omega_out: mean -0.2, sd 0.2; half-width 3.18245 x 0.1 = 0.31825: [-0.518, +0.118] holds 0.
  const PairedComponent& w = c.components[2];
  EXPECT_NEAR(w.mean, -0.2, 1e-12);
  EXPECT_NEAR(w.hi, 0.118245, 1e-5);
  EXPECT_TRUE(w.interval_holds_zero);
  EXPECT_TRUE(w.within_margin);
  EXPECT_FALSE(c.all_hold);
  // A margin of 0.6 sd lets V_out^x hold too.
  const PairedComparison m = paired_comparison(four_pairs(), "A-", "B-", kScale, {0.95, 0.6});
  EXPECT_TRUE(m.components[0].within_margin);
  EXPECT_TRUE(m.all_hold);
}

TEST(Paired, AnIdBelongsToTheLongestPrefixItStartsWith) {
  ImpactSet s;
  s.source = "overlap";
  s.impacts = {impact("E1-a", "cylinder", 3, 1, -40), impact("E10-a", "cylinder", 3.5, 1, -40),
               impact("E1-b", "cylinder", 3, 1, -40), impact("E10-b", "cylinder", 3.5, 1, -40)};
  const PairedComparison c = paired_comparison(s, "E1", "E10", kScale);
  ASSERT_EQ(c.keys.size(), 2u);
  EXPECT_EQ(c.keys[0], "-a");
  EXPECT_NEAR(c.components[0].mean, 1.0, 1e-12);  // 0.5 m/s over a 0.5 m/s scale
  EXPECT_TRUE(c.unpaired.empty());
}

TEST(Paired, BadInputNamesWhatIsWrong) {
  const ImpactSet s = four_pairs();
  EXPECT_THROW(paired_comparison(s, "A-", "A-", kScale), std::invalid_argument);
  EXPECT_THROW(paired_comparison(s, "A-", "B-", kScale, {1.5, 0.25}), InputError);
  try {
    paired_comparison(s, "A-", "B-", {{"cylinder", {0.5, 0.2, 10.0}}});
    FAIL() << "no scale for the triangles";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "shape");
    EXPECT_NE(std::string(e.what()).find("triangle"), std::string::npos) << e.what();
  }
  try {
    paired_comparison(s, "X-", "Y-", kScale);
    FAIL() << "no pair";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "id");
  }
}

}  // namespace
}  // namespace ricochet::stats
