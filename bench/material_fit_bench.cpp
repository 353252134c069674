// `slicecap fit` speed: one table's fit on one core (issue 30 goal: < 1 s). The fit is all of the
// command's time but the EXR read and the JSON write (a few ms). Four kinds of table: a GGX one
// (fitted exactly, the sheen and the coat skipped), a Ward one (no model fits exactly: every
// candidate solved), a velvet (the sheen chosen) and a lacquer (the coat chosen). Each also
// without the coat candidate (`NoCoat`): the baseline of what the coat costs, in the same run.
#include <benchmark/benchmark.h>

#include "slicecap/fit/material_fit.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace {

using namespace slicecap;

void fitTable(benchmark::State& state, const Abrdf& table, bool tryCoat) {
  fit::FitOptions options;
  options.tryCoat = tryCoat;
  for (auto _ : state)
    benchmark::DoNotOptimize(fit::fitMaterial(table, "bench", options));
}

Abrdf builtIn(const char* material) { return models::tabulate(*models::findMaterial(material)); }

// A rough red dielectric under a glossy clear coat (tests/fit/material_fit_test.cpp's lacquer).
Abrdf lacquer() {
  fit::FittedMaterial m;
  m.model = fit::MaterialModel::GgxCoat;
  m.diffuseAlbedo = {0.35, 0.05, 0.04};
  m.specularF0 = Rgb::gray(0.04);
  m.alphaTangent = m.alphaBitangent = 0.35;
  m.coatWeight = 0.8;
  m.coatAlpha = 0.06;
  return fit::tabulate(m);
}

void BM_FitGgxTable(benchmark::State& s) { fitTable(s, builtIn("brushed-steel-30"), true); }
void BM_FitWardTable(benchmark::State& s) { fitTable(s, builtIn("satin-blue-45"), true); }
void BM_FitWardTableNoCoat(benchmark::State& s) { fitTable(s, builtIn("satin-blue-45"), false); }
void BM_FitVelvetTable(benchmark::State& s) { fitTable(s, builtIn("velvet-green-20"), true); }
void BM_FitVelvetTableNoCoat(benchmark::State& s) {
  fitTable(s, builtIn("velvet-green-20"), false);
}
void BM_FitLacquerTable(benchmark::State& s) { fitTable(s, lacquer(), true); }
void BM_FitLacquerTableNoCoat(benchmark::State& s) { fitTable(s, lacquer(), false); }

BENCHMARK(BM_FitGgxTable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitWardTable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitWardTableNoCoat)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitVelvetTable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitVelvetTableNoCoat)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitLacquerTable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitLacquerTableNoCoat)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
