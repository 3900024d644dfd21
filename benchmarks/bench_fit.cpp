// Calibration speed (issue 4): all 59 lab releases (28 cylinders + 31 triangles, paper Appendix A)
// calibrated per release with paper Eq. 7 in under 2 s on this 2-core machine, at the paper's
// time step dt = 1e-5 s.
//
//   BM_CalibrateLab/0  point calibration (LHS design + 4 BOBYQA starts per release; triangles
//                      also fit their incidence angle): the 2 s target
//   BM_CalibrateLab/1  the same plus the near-optimal (identifiability) intervals of every
//                      parameter of every release
// Counters: releases, collisions simulated, collisions per second, and e_n^2 mean of the
// cylinders (paper Table 4: 0.15) as a check that the fast path computes the right thing.
//
// Run: build/benchmarks/bench_fit --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include "fit/fit.hpp"
#include "stats/stats.hpp"

namespace {

using namespace ricochet;

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

void BM_CalibrateLab(benchmark::State& state) {
  const ImpactSet cyl = read_impact_set(kLab + "cylinders.csv");
  const ImpactSet tri = read_impact_set(kLab + "triangles.csv");
  const Model model = Model::paper();
  fit::FitOptions o;
  o.intervals = state.range(0) != 0;
  double collisions = 0, en2 = 0;
  for (auto _ : state) {
    const auto a = fit::calibrate_releases(model, Shape::cylinder(), cyl, o);
    const auto b = fit::calibrate_releases(model, Shape::triangle(), tri, o);
    collisions = 0;
    std::vector<double> v;
    for (const auto& f : a) collisions += f.evaluations, v.push_back(f.value("en2"));
    for (const auto& f : b) collisions += f.evaluations;
    en2 = stats::summarize(v).mean;
    benchmark::DoNotOptimize(b.data());
  }
  state.counters["releases"] = static_cast<double>(cyl.size() + tri.size());
  state.counters["collisions"] = collisions;
  state.counters["collisions_per_s"] =
      benchmark::Counter(collisions, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["cyl_en2_mean"] = en2;
  state.counters["dt_s"] = o.engine.dt_s;
}
BENCHMARK(BM_CalibrateLab)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);

void BM_CalibrateShape(benchmark::State& state) {
  const bool triangle = state.range(0) != 0;
  const ImpactSet set = read_impact_set(kLab + (triangle ? "triangles.csv" : "cylinders.csv"));
  fit::FitOptions o;
  o.intervals = state.range(1) != 0;
  for (auto _ : state) {
    const auto fits = fit::calibrate_releases(
        Model::paper(), triangle ? Shape::triangle() : Shape::cylinder(), set, o);
    benchmark::DoNotOptimize(fits.data());
  }
  state.counters["releases"] = static_cast<double>(set.size());
}
BENCHMARK(BM_CalibrateShape)
    ->ArgNames({"triangle", "intervals"})
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
