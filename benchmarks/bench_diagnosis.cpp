// Diagnosis speed (issue 6): "diagnosis of a whole ladder is cheap enough to be interactive:
// seconds on the lab data". Each benchmark runs the full `ricochet diagnose` computation (base
// population fit, 5-fold held-out error, noise floor, per-release fits with identifiability
// intervals, and every catalog candidate recalibrated with its own 5-fold held-out error) on one
// shape of the lab data (paper Appendix A), at the paper's time step dt = 1e-5 s.
//
//   BM_DiagnoseLab/0   28 cylinders
//   BM_DiagnoseLab/1   31 triangles (orientation unknown: fits search on 6 orientations and
//                      polish on 24, every prediction is an average over 24, cold fits run 32
//                      starts; fit/orientation_rule.hpp; a triangle collision costs 6-10 cylinder
//                      collisions)
//   BM_CompareLab/0,1  compare only (base model, no candidates)
//   BM_CompareLab/2    the triangles' compare with the response-surface search
//                      (--orientation-search surface, fit/surrogate_search.hpp)
// Counters: releases, candidates tried, the base held-out error and the noise floor (checks that
// the fast path computes the right thing; docs/diagnosis.md lists the values), and the
// collisions simulated (engine.hpp, collisions_simulated: the cost account of issue 35, item 3).
//
// Target (issue 10): the lab cylinders diagnosed, leak-free, in <= 3 s on 2 cores. Shown as a
// ratio to the plain scalar reference (plain_scalar.hpp) measured in the same run:
// BM_PlainScalarReference50k times 50,000 reference collisions; scripts/bench.sh prints
// diagnose / reference.
//
// Run: build/benchmarks/bench_diagnosis --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cstdint>

#include "diagnosis/diagnose.hpp"
#include "engine/engine.hpp"
#include "plain_scalar.hpp"

namespace {

using namespace ricochet;

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

ImpactSet lab(bool triangle) {
  return read_impact_set(kLab + (triangle ? "triangles.csv" : "cylinders.csv"));
}

void BM_DiagnoseLab(benchmark::State& state) {
  const bool triangle = state.range(0) != 0;
  const ImpactSet set = lab(triangle);
  diagnosis::DiagnoseOptions o;
  o.progress = false;
  double base = 0, floor = 0, candidates = 0;
  const std::uint64_t before = collisions_simulated();
  for (auto _ : state) {
    const auto d = diagnosis::diagnose(Model::paper(),
                                       triangle ? Shape::triangle() : Shape::cylinder(), set, o);
    base = d.baseline.base.heldout.error.mean;
    floor = d.baseline.floor.value.mean;
    candidates = static_cast<double>(d.family_size);
    benchmark::DoNotOptimize(d.ranking.data());
  }
  state.counters["releases"] = static_cast<double>(set.size());
  state.counters["candidates"] = candidates;
  state.counters["base_heldout_error"] = base;
  state.counters["noise_floor"] = floor;
  state.counters["collisions"] = static_cast<double>(collisions_simulated() - before);
}
BENCHMARK(BM_DiagnoseLab)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

// 50,000 collisions of the plain scalar reference at the lab mean state (issue 13's unit).
void BM_PlainScalarReference50k(benchmark::State& state) {
  double sink = 0;
  for (auto _ : state)
    for (int k = 0; k < 50000; ++k)
      sink += bench::plain_scalar_collision(0.15, 0.23, 0.16, bench::kLabMean.vin, 1e-5)[0];
  benchmark::DoNotOptimize(sink);
}
BENCHMARK(BM_PlainScalarReference50k)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_CompareLab(benchmark::State& state) {
  const bool triangle = state.range(0) != 0;
  const ImpactSet set = lab(triangle);
  diagnosis::DiagnoseOptions o;
  o.progress = false;
  if (state.range(0) == 2) o.assess.fit.alpha.search = fit::OrientationSearch::kSurface;
  double heldout = 0;
  const std::uint64_t before = collisions_simulated();
  for (auto _ : state) {
    const auto b = diagnosis::compare(Model::paper(),
                                      triangle ? Shape::triangle() : Shape::cylinder(), set, o);
    benchmark::DoNotOptimize(b.base.heldout.per_release.data());
    heldout = b.base.heldout.error.mean;
  }
  state.counters["releases"] = static_cast<double>(set.size());
  state.counters["base_heldout_error"] = heldout;
  state.counters["collisions"] = static_cast<double>(collisions_simulated() - before);
}
BENCHMARK(BM_CompareLab)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
