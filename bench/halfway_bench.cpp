// The halfway method: one RGB ABRDF on one core, against Method B (its baseline and, for
// isotropic materials, its inner part). The neighbour tables are built once (timed separately).
#include <benchmark/benchmark.h>

#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/halfway_method.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace {

using namespace slicecap;

SliceSet slicesOf(const char* material) {
  return recon::extractSlices(models::tabulate(*models::findMaterial(material)));
}

void BM_HalfwaySystemBuild(benchmark::State& state) {
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::HalfwaySystem(recon::HalfwayParams{}));
}
BENCHMARK(BM_HalfwaySystemBuild)->Unit(benchmark::kMillisecond);

void BM_Halfway_Anisotropic_168Samples(benchmark::State& state) {
  const SliceSet slices = slicesOf("brushed-steel-30");
  recon::reconstructHalfway(slices);  // builds the shared system outside the timing
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructHalfway(slices));
}
BENCHMARK(BM_Halfway_Anisotropic_168Samples)->Unit(benchmark::kMillisecond);

void BM_Halfway_Isotropic_168Samples(benchmark::State& state) {
  const SliceSet slices = slicesOf("blue-plastic");
  recon::reconstructHalfway(slices);
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructHalfway(slices));
}
BENCHMARK(BM_Halfway_Isotropic_168Samples)->Unit(benchmark::kMillisecond);

void BM_MethodB_168Samples(benchmark::State& state) {
  const SliceSet slices = slicesOf("brushed-steel-30");
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructMethodB(slices));
}
BENCHMARK(BM_MethodB_168Samples)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
