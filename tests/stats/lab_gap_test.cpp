// The model-against-lab comparison: gross errors found from the measurements alone, the response
// test telling measurement noise from a real change of input, the exit slip of a disc.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "stats/lab_gap.hpp"

namespace ricochet {
namespace {

// A measured set made the way the lab's appears to be: every release has the same true incident
// state; the measured V_in and V_out both carry independent reading noise; `gross` releases get a
// spin read 35 rad/s off. The model set is a deterministic linear response run at the MEASURED
// inputs (as a resolved campaign at the lab's states is). Magnitudes are the lab cylinders'.
struct Sets {
  ImpactSet model, measured;
};
Sets make_sets(std::uint64_t seed, bool measured_responds, int gross) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const Vel3 mean_in = {2.9, -2.3, -65.0}, noise_in = {0.21, 0.19, 5.9};
  const Vel3 noise_out = {0.12, 0.15, 3.0};
  // Response of V_out to V_in, component by component (resolved cylinders' slopes, roughly).
  const Vel3 slope = {0.85, -0.3, 0.6}, mean_out = {3.0, 0.85, -40.0};
  Sets s;
  for (int i = 0; i < 28; ++i) {
    Impact m, l;
    m.id = l.id = "R" + std::to_string(i);
    m.shape = l.shape = "cylinder";
    Vel3 true_in = mean_in;
    // A set that responds: its incident states really differ, by the measured spread.
    if (measured_responds)
      for (int k = 0; k < 3; ++k) true_in[k] += noise_in[k] * n(rng);
    for (int k = 0; k < 3; ++k) {
      l.vin[k] = measured_responds ? true_in[k] : true_in[k] + noise_in[k] * n(rng);
      const double response = mean_out[k] + slope[k] * (true_in[k] - mean_in[k]);
      l.vout[k] = response + noise_out[k] * n(rng);
      m.vin[k] = l.vin[k];
      m.vout[k] = mean_out[k] + slope[k] * (m.vin[k] - mean_in[k]);
    }
    if (i < gross) l.vout[kW] -= 35.0;
    s.model.impacts.push_back(m);
    s.measured.impacts.push_back(l);
  }
  return s;
}

TEST(LabGap, NoisyInputsAreToldFromARealResponse) {
  // 200 seeds each: the rate at which the Holm-adjusted response test rejects on the spin.
  int rejected_noisy = 0, rejected_real = 0;
  const int reps = 200;
  for (int r = 0; r < reps; ++r) {
    const Sets a = make_sets(1000 + r, false, 0);
    const Sets b = make_sets(5000 + r, true, 0);
    rejected_noisy += stats::lab_gap(a.model, a.measured, {}).response_p_holm[kW] < 0.05;
    rejected_real += stats::lab_gap(b.model, b.measured, {}).response_p_holm[kW] < 0.05;
  }
  // Power on noise-dominated inputs (lab-like: slope 0.6 against about 0, se about 0.1).
  EXPECT_GT(rejected_noisy, 0.95 * reps);
  // A measured set that does respond, with output noise: equal slopes, so at most the level
  // (Holm makes it smaller). 5 % of 200 is 10; the binomial 99.9 % upper bound is 21.
  EXPECT_LE(rejected_real, 21);
}

TEST(LabGap, GrossErrorsComeFromTheMeasurementsAndFormTheCore) {
  const Sets s = make_sets(42, false, 2);
  stats::LabGapOptions o;
  o.disc_radius_m = 0.08;
  const auto g = stats::lab_gap(s.model, s.measured, o);
  // The two spins read 35 rad/s off (about 10 MAD) are flagged; clean releases rarely are.
  ASSERT_GE(g.flagged_ids.size(), 2u);
  EXPECT_EQ(g.flagged_ids[0], "R0");
  EXPECT_EQ(g.flagged_ids[1], "R1");
  ASSERT_EQ(g.components.size(), 4u);
  EXPECT_EQ(g.components[3].name, "slip_out");
  // The exit slip is V_out^x + omega R, computed on each side.
  const double slip0 = s.model.impacts[0].vout[kVx] + 0.08 * s.model.impacts[0].vout[kW];
  EXPECT_NEAR(g.components[3].model.min <= slip0 && slip0 <= g.components[3].model.max, 1, 0);
  ASSERT_TRUE(g.components[kW].measured_core.has_value());
  EXPECT_EQ(g.components[kW].measured_core->n, 28 - g.flagged_ids.size());
  // Without the two gross errors the lab's spin sd falls to its reading noise.
  EXPECT_LT(g.components[kW].measured_core->std, 0.5 * g.components[kW].measured.std);
  const auto j = stats::checks_json(g);
  EXPECT_EQ(j["lab_gross_errors"][0]["id"], "R0");
  EXPECT_TRUE(j["lab_response"].contains("w"));
  EXPECT_TRUE(stats::to_json(g.components[kW]).contains("lab_core"));
}

TEST(LabGap, NoCoreWithoutGrossErrors) {
  const std::vector<double> a = {1, 2, 3, 4}, b = {1.5, 2.5, 3.5, 4.5};
  const auto g = stats::component_gap("x", a, b);
  EXPECT_FALSE(g.measured_core.has_value());
  EXPECT_FALSE(stats::to_json(g).contains("lab_core"));
  EXPECT_THROW(stats::lab_gap(ImpactSet{}, ImpactSet{}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace ricochet
