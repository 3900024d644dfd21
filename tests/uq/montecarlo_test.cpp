// Monte Carlo (paper section 4.3): reproducibility from the seed, independence from chunking,
// CDF comparison against data drawn from the same or another model, the lab comparison the
// paper's Fig. 16 shows, range calibration recovering known ranges, resumable HDF5 runs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "fit/fit.hpp"
#include "stats/stats.hpp"
#include "uq/montecarlo.hpp"
#include "uq/uq_io.hpp"

namespace ricochet::uq {
namespace {

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

std::vector<ParameterInput> paper_inputs() {
  std::vector<ParameterInput> in;
  for (const auto& [name, r] : paper_ranges())
    in.push_back({name, Distribution::uniform(r.first, r.second)});
  return in;
}

MonteCarloOptions small(std::size_t runs, std::uint64_t seed = 1) {
  MonteCarloOptions o;
  o.runs = runs;
  o.seed = seed;
  o.progress = false;
  return o;
}

// An impact set whose reflected velocities are Monte Carlo runs (the "measurements").
ImpactSet as_impacts(const MonteCarloResult& mc, std::size_t n) {
  ImpactSet set;
  set.source = "synthetic";
  for (std::size_t i = 0; i < n; ++i) {
    Impact im;
    im.id = "S" + std::to_string(i);
    im.shape = "cylinder";
    im.vin = mc.vin[i];
    im.vout = mc.vout[i];
    set.impacts.push_back(im);
  }
  return set;
}

TEST(MonteCarlo, ReproducibleFromTheSeedAndIndependentOfChunking) {
  const Model model = Model::paper();
  const Shape shape = Shape::cylinder();
  MonteCarloOptions o = small(3000);
  const MonteCarloResult a = run_monte_carlo(model, shape, paper_inputs(), o);
  o.chunk = 700;
  o.engine.threads = 1;
  const MonteCarloResult b = run_monte_carlo(model, shape, paper_inputs(), o);
  ASSERT_EQ(a.size(), 3000u);
  EXPECT_EQ(a.vout, b.vout);
  EXPECT_EQ(a.inputs, b.inputs);
  const MonteCarloResult c = run_monte_carlo(model, shape, paper_inputs(), small(3000, 2));
  EXPECT_NE(a.vout, c.vout);
  // Inputs follow their uniform ranges.
  const auto in = paper_inputs();
  for (std::size_t k = 0; k < in.size(); ++k) {
    double lo = 1e9, hi = -1e9, mean = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double x = a.inputs[i * in.size() + k];
      lo = std::min(lo, x);
      hi = std::max(hi, x);
      mean += x / a.size();
    }
    EXPECT_GE(lo, in[k].distribution.lower());
    EXPECT_LE(hi, in[k].distribution.upper());
    EXPECT_NEAR(mean, 0.5 * (in[k].distribution.lower() + in[k].distribution.upper()),
                0.03 * (in[k].distribution.upper() - in[k].distribution.lower()));
  }
  for (int s : a.status) EXPECT_EQ(s, 0);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.vin[i], (Vel3{2.9, -2.3, -65.0}));
}

TEST(MonteCarlo, KsAcceptsTheSameModelAndRejectsAnother) {
  const Model model = Model::paper();
  const Shape shape = Shape::cylinder();
  // "Measurements": 40 runs of the paper's ranges with another seed.
  const ImpactSet same =
      as_impacts(run_monte_carlo(model, shape, paper_inputs(), small(40, 7)), 40);
  const MonteCarloResult mc = run_monte_carlo(model, shape, paper_inputs(), small(5000));
  const CdfComparison c = compare_cdfs(mc, same);
  for (int k = 0; k < 3; ++k) EXPECT_GT(c.p_value[k], 0.01) << kComponentNames[k];
  // Data from a higher restitution: V_out^y is rejected.
  std::vector<ParameterInput> high = paper_inputs();
  for (auto& in : high)
    if (in.name == "en2") in.distribution = Distribution::uniform(0.4, 0.5);
  const ImpactSet other = as_impacts(run_monte_carlo(model, shape, high, small(40, 7)), 40);
  const CdfComparison d = compare_cdfs(mc, other);
  EXPECT_LT(d.p_value[kVy], 1e-4);
  EXPECT_GT(d.ks[kVy], 0.5);
  EXPECT_GT(d.cvm[kVy], c.cvm[kVy]);
}

TEST(MonteCarlo, LabCylindersVersusThePaperRanges) {
  // Fig. 16 of the paper: the paper's uniform ranges at the mean incident state. Our engine
  // reproduces V_out^y and omega_out (KS p > 0.05) but over-predicts V_out^x by about 0.3 m/s
  // (docs/calibration.md): the KS test rejects V_out^x. This test pins that documented finding.
  const ImpactSet lab = read_impact_set(kLab + "cylinders.csv");
  const MonteCarloResult mc =
      run_monte_carlo(Model::paper(), Shape::cylinder(), paper_inputs(), small(20000));
  const CdfComparison c = compare_cdfs(mc, lab);
  EXPECT_GT(c.p_value[kVy], 0.05);
  EXPECT_GT(c.p_value[kW], 0.05);
  EXPECT_LT(c.p_value[kVx], 1e-6);
  const double sim_vx = stats::summarize(mc.component(kVx)).mean;
  const double lab_vx = stats::summarize(lab.feature("vout_x")).mean;
  EXPECT_NEAR(sim_vx - lab_vx, 0.3, 0.15);
}

TEST(MonteCarlo, ResampledIncidentStatesComeFromTheData) {
  const ImpactSet lab = read_impact_set(kLab + "cylinders.csv");
  MonteCarloOptions o = small(500);
  o.incident = &lab;
  const MonteCarloResult mc = run_monte_carlo(Model::paper(), Shape::cylinder(), paper_inputs(), o);
  std::size_t distinct = 0;
  std::vector<bool> used(lab.size(), false);
  for (const Vel3& v : mc.vin) {
    bool found = false;
    for (std::size_t i = 0; i < lab.size(); ++i)
      if (lab.impacts[i].vin == v) {
        found = true;
        if (!used[i]) used[i] = true, ++distinct;
      }
    EXPECT_TRUE(found);
  }
  EXPECT_GT(distinct, 20u);  // 500 draws with replacement out of 28
}

TEST(MonteCarlo, UnknownParameterOrOutOfBoundsDistributionIsRejected) {
  std::vector<ParameterInput> in = {{"e_n", Distribution::uniform(0.1, 0.2)}};
  EXPECT_THROW(run_monte_carlo(Model::paper(), Shape::cylinder(), in, small(10)),
               std::invalid_argument);
  in = {{"en2", Distribution::uniform(0.5, 1.5)}};
  EXPECT_THROW(run_monte_carlo(Model::paper(), Shape::cylinder(), in, small(10)),
               std::invalid_argument);
}

TEST(RangeCalibration, RecoversTheRangeThatGeneratedTheData) {
  const Model model = Model::paper();
  const Shape shape = Shape::cylinder();
  // Data: en2 uniform on [0.1, 0.2] (mu, muR fixed at the model values).
  const std::vector<ParameterInput> truth = {{"en2", Distribution::uniform(0.1, 0.2)}};
  const ImpactSet data = as_impacts(run_monte_carlo(model, shape, truth, small(300, 11)), 300);
  RangeFitOptions o;
  o.mc.runs = 600;
  o.max_evaluations = 150;
  const std::vector<ParameterInput> start = {{"en2", Distribution::uniform(0.05, 0.3)}};
  const RangeFitResult r = calibrate_ranges(model, shape, data, start, o);
  ASSERT_EQ(r.ranges.size(), 1u);
  EXPECT_LT(r.distance, r.initial_distance);
  EXPECT_NEAR(r.ranges[0].distribution.lower(), 0.1, 0.02);
  EXPECT_NEAR(r.ranges[0].distribution.upper(), 0.2, 0.02);
  EXPECT_GT(r.comparison.p_value[kVy], 0.05);
}

TEST(Distribution, FittedDistributionFollowsItsSampleWithinBounds) {
  std::vector<double> v;
  for (int i = 0; i < 40; ++i) v.push_back(0.15 + 0.05 * std::sin(1.7 * i));
  const Distribution d = Distribution::fitted(v, 0.0, 1.0);
  EXPECT_GE(d.lower(), 0.0);
  EXPECT_LE(d.upper(), 1.0);
  EXPECT_NEAR(d.quantile(0.5), 0.15, 0.03);
  EXPECT_NEAR(d.cdf(d.quantile(0.3)), 0.3, 1e-6);
  EXPECT_FALSE(d.is_uniform());
  EXPECT_THROW(Distribution::fitted(std::vector<double>{0.1, 0.1, 0.1}, 0, 1),
               std::invalid_argument);
  EXPECT_THROW(Distribution::uniform(0.3, 0.2), std::invalid_argument);
}

TEST(MonteCarloStore, KilledRunResumesToTheSameResult) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("ricochet-mc-store-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "mc.h5").string();
  const Model model = Model::paper();
  const Shape shape = Shape::cylinder();
  MonteCarloOptions o = small(2000);
  o.chunk = 500;
  const MonteCarloResult full = run_monte_carlo(model, shape, paper_inputs(), o);
  {
    // Killed after two chunks: the callback stops the run by throwing.
    MonteCarloStore store(path, model, shape, paper_inputs(), o, "", false);
    EXPECT_THROW(run_monte_carlo(model, shape, paper_inputs(), o,
                                 [&](std::size_t b, std::size_t e, const MonteCarloResult& r) {
                                   store.append(b, e, r);
                                   if (e >= 1000) throw std::runtime_error("killed");
                                 }),
                 std::runtime_error);
  }
  MonteCarloStore store(path, model, shape, paper_inputs(), o, "", true);
  EXPECT_EQ(store.done_runs(), 1000u);
  std::size_t simulated = 0;
  MonteCarloResult resumed = run_monte_carlo(
      model, shape, paper_inputs(), o,
      [&](std::size_t b, std::size_t e, const MonteCarloResult& r) {
        simulated += e - b;
        store.append(b, e, r);
      },
      store.done_runs());
  store.load(resumed);
  EXPECT_EQ(simulated, 1000u);
  EXPECT_EQ(resumed.vout, full.vout);
  EXPECT_EQ(resumed.inputs, full.inputs);
  // Other settings cannot resume this file.
  MonteCarloOptions other = o;
  other.seed = 5;
  EXPECT_THROW(MonteCarloStore(path, model, shape, paper_inputs(), other, "", true),
               ricochet::InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ricochet::uq
