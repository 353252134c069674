// Prior reconstruction speed: one RGB ABRDF on one core (anisotropic: brushed steel; isotropic:
// blue plastic), against Method B in the same run (goal < 1 ms, the budget of Method B).
#include <benchmark/benchmark.h>

#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace {

using namespace slicecap;

SliceSet slicesOf(const char* material, bool diagonalOnly = false) {
  recon::ExtractionParams params;
  params.diagonalOnly = diagonalOnly;
  return recon::extractSlices(models::tabulate(*models::findMaterial(material)), params);
}

// One prior reconstruction per iteration, from the ideal slices of a built-in material.
void reconstructEachIteration(benchmark::State& state, const char* material,
                              bool diagonalOnly = false) {
  const SliceSet slices = slicesOf(material, diagonalOnly);
  const prior::PriorModel& model = prior::defaultPriorModel();
  for (auto _ : state)
    benchmark::DoNotOptimize(prior::reconstructWithPrior(slices, model));
}

void BM_Prior_168Samples(benchmark::State& state) {
  reconstructEachIteration(state, "brushed-steel-30");
}
BENCHMARK(BM_Prior_168Samples)->Unit(benchmark::kMicrosecond);

void BM_Prior_168Samples_Isotropic(benchmark::State& state) {
  reconstructEachIteration(state, "blue-plastic");
}
BENCHMARK(BM_Prior_168Samples_Isotropic)->Unit(benchmark::kMicrosecond);

// A near-diffuse material: the prior is blended with Method B (PriorParams::blendWithMethodB),
// so this is the prior and Method B together.
void BM_Prior_168Samples_NearDiffuseBlended(benchmark::State& state) {
  reconstructEachIteration(state, "matte-paint");
}
BENCHMARK(BM_Prior_168Samples_NearDiffuseBlended)->Unit(benchmark::kMicrosecond);

void BM_Prior_Diagonal84Samples(benchmark::State& state) {
  reconstructEachIteration(state, "blue-plastic", true);
}
BENCHMARK(BM_Prior_Diagonal84Samples)->Unit(benchmark::kMicrosecond);

void BM_MethodB_168Samples_Baseline(benchmark::State& state) {
  const SliceSet slices = slicesOf("brushed-steel-30");
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructMethodB(slices));
}
BENCHMARK(BM_MethodB_168Samples_Baseline)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
