// `slicecap fit` speed: one table's fit on one core (issue 30 goal: < 1 s). The fit is all of the
// command's time but the EXR read and the JSON write (a few ms). Three kinds of table: a GGX one
// (fitted exactly, the sheen skipped), a Ward one (no model fits exactly: both candidates solved),
// a velvet (the sheen chosen).
#include <benchmark/benchmark.h>

#include "slicecap/fit/material_fit.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace {

using namespace slicecap;

void fitBuiltIn(benchmark::State& state, const char* material) {
  const Abrdf table = models::tabulate(*models::findMaterial(material));
  for (auto _ : state)
    benchmark::DoNotOptimize(fit::fitMaterial(table, material));
}

void BM_FitGgxTable(benchmark::State& state) { fitBuiltIn(state, "brushed-steel-30"); }
BENCHMARK(BM_FitGgxTable)->Unit(benchmark::kMillisecond);

void BM_FitWardTable(benchmark::State& state) { fitBuiltIn(state, "satin-blue-45"); }
BENCHMARK(BM_FitWardTable)->Unit(benchmark::kMillisecond);

void BM_FitVelvetTable(benchmark::State& state) { fitBuiltIn(state, "velvet-green-20"); }
BENCHMARK(BM_FitVelvetTable)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
