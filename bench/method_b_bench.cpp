// Method B speed: one RGB ABRDF from 168 (and 192) samples on one core; goal < 1 ms (paper: ~0.3 s
// on a 3-core 2.7 GHz Xeon). Parts are timed too, to show where the time goes.
#include <benchmark/benchmark.h>

#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/lafortune_fit.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace {

using namespace slicecap;

SliceSet slicesOf(const char* material, std::optional<double> stepDeg = std::nullopt) {
  recon::ExtractionParams params;
  params.stepDeg = stepDeg;
  return recon::extractSlices(models::tabulate(*models::findMaterial(material)), params);
}

void BM_MethodB_168Samples(benchmark::State& state) {
  const SliceSet slices = slicesOf("brushed-steel-30");
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructMethodB(slices));
}
BENCHMARK(BM_MethodB_168Samples)->Unit(benchmark::kMicrosecond);

void BM_MethodB_192Samples(benchmark::State& state) {
  const SliceSet slices = slicesOf("brushed-steel-30", 15.0);
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructMethodB(slices));
}
BENCHMARK(BM_MethodB_192Samples)->Unit(benchmark::kMicrosecond);

void BM_MethodB_Isotropic84Samples(benchmark::State& state) {
  const SliceSet slices = slicesOf("blue-plastic");
  recon::MethodBParams params;
  params.isotropic = true;
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructMethodB(slices, params));
}
BENCHMARK(BM_MethodB_Isotropic84Samples)->Unit(benchmark::kMicrosecond);

void BM_SliceSumSubspace75x75(benchmark::State& state) {
  const SliceSet slices = slicesOf("brushed-steel-30");
  const Slice& a = *slices.find({SliceKind::Axial, {75, 75}});
  const Slice& d = *slices.find({SliceKind::Diagonal, {75, 75}});
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructSubspace(a, d));
}
BENCHMARK(BM_SliceSumSubspace75x75)->Unit(benchmark::kMicrosecond);

void BM_CeresLobeFit48Samples(benchmark::State& state) {
  std::vector<recon::ElevationSample> samples;
  for (int k = 0; k < 24; ++k) {
    samples.push_back({30.0, 0.5 + 0.01 * (k % 5)});
    samples.push_back({75.0, 0.2 + 0.01 * (k % 3)});
  }
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::fitElevationLobe(samples));
}
BENCHMARK(BM_CeresLobeFit48Samples)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
