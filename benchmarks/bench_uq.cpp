// Monte Carlo and Sobol speed (issue 4): 50,000 Monte Carlo collisions (paper section 4.3:
// uniform e_n^2, mu, mu_R over the paper's ranges, incident state (2.9, -2.3, -65)) in under
// 0.5 s on this 2-core machine at dt = 1e-5 s; and a Sobol analysis with second order
// (N = 4096: 32,768 collisions plus the OpenTURNS estimators and bootstrap).
//
// Run: build/benchmarks/bench_uq --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include "uq/montecarlo.hpp"
#include "uq/sobol.hpp"

namespace {

using namespace ricochet;

std::vector<uq::ParameterInput> paper_inputs() {
  std::vector<uq::ParameterInput> in;
  for (const auto& [name, r] : uq::paper_ranges())
    in.push_back({name, uq::Distribution::uniform(r.first, r.second)});
  return in;
}

void BM_MonteCarlo(benchmark::State& state) {
  uq::MonteCarloOptions o;
  o.runs = static_cast<std::size_t>(state.range(0));
  o.progress = false;
  const auto in = paper_inputs();
  for (auto _ : state) {
    const auto r = uq::run_monte_carlo(Model::paper(), Shape::cylinder(), in, o);
    benchmark::DoNotOptimize(r.vout.data());
  }
  state.counters["runs_per_s"] = benchmark::Counter(static_cast<double>(o.runs),
                                                    benchmark::Counter::kIsIterationInvariantRate);
  state.counters["dt_s"] = o.engine.dt_s;
}
BENCHMARK(BM_MonteCarlo)->Arg(50000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

void BM_SobolCylinder(benchmark::State& state) {
  uq::SobolOptions o;
  o.base_size = static_cast<std::size_t>(state.range(0));
  const auto in = paper_inputs();
  for (auto _ : state) {
    const auto r =
        uq::collision_sobol(Model::paper(), Shape::cylinder(), in,
                            {uq::kPaperVin[0], uq::kPaperVin[1], uq::kPaperVin[2]}, 0.0, o);
    benchmark::DoNotOptimize(r.first.data());
  }
  state.counters["collisions"] = static_cast<double>(o.base_size * 8);
}
BENCHMARK(BM_SobolCylinder)->Arg(4096)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
