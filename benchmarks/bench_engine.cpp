// Engine throughput against a plain scalar implementation of the same law.
//
// Target (issue: reduced engine): >= 200,000 cylinder collisions per second on this 2-core
// machine at the paper's mean incident state (2.9, -2.3, -65) with the paper's parameters,
// versus ~16,000 per second per core for a plain scalar implementation that keeps integrating
// 5 ms of free flight after separation. The speed comes from design (stop at separation,
// structure-of-arrays lanes the compiler vectorises, no allocation in the step loop), not from
// looser physics: every run checks V_out against a reference step of dt / 10.
//
// Run: ./run.sh bench  (or build/benchmarks/bench_engine)
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "effects/model.hpp"
#include "engine/engine.hpp"
#include "plain_scalar.hpp"

namespace {

using ricochet::CollisionCase;
using ricochet::EngineOptions;
using ricochet::Model;
using ricochet::Shape;
using ricochet::Vel3;

using ricochet::bench::kLabMean;
using ricochet::bench::plain_scalar_collision;

void BM_PlainScalarBaseline(benchmark::State& state) {
  Vel3 v{};
  for (auto _ : state) {
    for (int k = 0; k < 1000; ++k) v = plain_scalar_collision(0.15, 0.23, 0.16, kLabMean.vin, 1e-5);
    benchmark::DoNotOptimize(v);
  }
  state.counters["collisions_per_s"] =
      benchmark::Counter(1000.0 * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["vout_x"] = v[0];
}
BENCHMARK(BM_PlainScalarBaseline)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EngineBatch(benchmark::State& state) {
  const Model model = Model::paper();
  const Shape shape = Shape::cylinder();
  const std::vector<CollisionCase> cases(200000, kLabMean);
  EngineOptions options;
  options.threads = static_cast<int>(state.range(0));
  // Physics check against a reference step ten times smaller.
  EngineOptions fine;
  fine.dt_s = options.dt_s / 10;
  const auto reference = ricochet::simulate(model, shape, kLabMean, {}, fine);
  std::vector<ricochet::CollisionResult> results;
  for (auto _ : state) {
    results = ricochet::simulate_batch(model, shape, cases, {}, options);
    benchmark::DoNotOptimize(results.data());
  }
  double dv = 0, dw = 0;
  for (int k = 0; k < 2; ++k) dv = std::max(dv, std::fabs(results[0].vout[k] - reference.vout[k]));
  dw = std::fabs(results[0].vout[2] - reference.vout[2]);
  if (dv > 2e-3 || dw > 0.05) state.SkipWithError("V_out drifted from the reference step");
  state.counters["collisions_per_s"] = benchmark::Counter(
      static_cast<double>(cases.size()) * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["dV_vs_ref_mps"] = dv;
  state.counters["dW_vs_ref_radps"] = dw;
  // Steps integrated per collision at this state: the work unit of the flop count (bench.sh).
  state.counters["steps_per_collision"] = std::round(results[0].end_time_s / options.dt_s);
}
BENCHMARK(BM_EngineBatch)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EngineTriangleBatch(benchmark::State& state) {
  const Model model = Model::paper();
  const Shape shape = Shape::triangle();
  std::vector<CollisionCase> cases;
  for (int k = 0; k < 20000; ++k) cases.push_back({{3.3, -2.2, -40.0}, 2.0944 * (k % 97) / 97.0});
  EngineOptions options;
  options.threads = 2;
  for (auto _ : state)
    benchmark::DoNotOptimize(ricochet::simulate_batch(model, shape, cases, {}, options));
  state.counters["collisions_per_s"] = benchmark::Counter(
      static_cast<double>(cases.size()) * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_EngineTriangleBatch)->Unit(benchmark::kMillisecond)->UseRealTime();

// The core clock, from a chain of dependent scalar additions (latency 3 cycles on AMD Zen 3-4
// and Intel cores since Skylake): the denominator of "fraction of peak" in bench.sh, since
// this VM exposes no cycle counters.
void BM_ClockEstimate(benchmark::State& state) {
#if defined(__x86_64__)
  constexpr long kAdds = 100'000'000;
  double x = 1.0;
  for (auto _ : state) {
    long n = kAdds;  // the whole loop in assembly: x stays in its register
    __asm__ volatile("1: vaddsd %0, %0, %0\n\tdec %1\n\tjnz 1b" : "+x"(x), "+r"(n));
  }
  benchmark::DoNotOptimize(x);
  state.counters["clock_GHz"] =
      benchmark::Counter(3.0 * kAdds * state.iterations() * 1e-9, benchmark::Counter::kIsRate);
#else
  state.SkipWithError("x86-64 only");
#endif
}
BENCHMARK(BM_ClockEstimate)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
