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

void BM_Prior_168Samples(benchmark::State& state) {
  const SliceSet slices = slicesOf("brushed-steel-30");
  const prior::PriorModel& model = prior::defaultPriorModel();
  for (auto _ : state)
    benchmark::DoNotOptimize(prior::reconstructWithPrior(slices, model));
}
BENCHMARK(BM_Prior_168Samples)->Unit(benchmark::kMicrosecond);

void BM_Prior_168Samples_Isotropic(benchmark::State& state) {
  const SliceSet slices = slicesOf("blue-plastic");
  const prior::PriorModel& model = prior::defaultPriorModel();
  for (auto _ : state)
    benchmark::DoNotOptimize(prior::reconstructWithPrior(slices, model));
}
BENCHMARK(BM_Prior_168Samples_Isotropic)->Unit(benchmark::kMicrosecond);

// A near-diffuse material: the prior is blended with Method B (PriorParams::blendWithMethodB),
// so this is the prior and Method B together.
void BM_Prior_168Samples_NearDiffuseBlended(benchmark::State& state) {
  const SliceSet slices = slicesOf("matte-paint");
  const prior::PriorModel& model = prior::defaultPriorModel();
  for (auto _ : state)
    benchmark::DoNotOptimize(prior::reconstructWithPrior(slices, model));
}
BENCHMARK(BM_Prior_168Samples_NearDiffuseBlended)->Unit(benchmark::kMicrosecond);

void BM_Prior_Diagonal84Samples(benchmark::State& state) {
  const SliceSet slices = slicesOf("blue-plastic", true);
  const prior::PriorModel& model = prior::defaultPriorModel();
  for (auto _ : state)
    benchmark::DoNotOptimize(prior::reconstructWithPrior(slices, model));
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
