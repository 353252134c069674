// Method A and the uniform baseline: one RGB ABRDF on one core. Goal: Method A under 50 ms per
// ABRDF (paper: ~1 s on a 3-core 2.7 GHz Xeon). The material-independent system is built once
// (timed separately) and reused, as it is in `eval` and in texture mode.
#include <benchmark/benchmark.h>

#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/measured_subspaces.hpp"
#include "slicecap/recon/method_a.hpp"
#include "slicecap/recon/scattered_rbf.hpp"
#include "slicecap/recon/slice_extraction.hpp"
#include "slicecap/recon/uniform_sampling.hpp"

namespace {

using namespace slicecap;

Abrdf truth() {
  return models::tabulate(*models::findMaterial("brushed-steel-30"));
}

void BM_MethodASystemBuild(benchmark::State& state) {
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::MethodASystem());
}
BENCHMARK(BM_MethodASystemBuild)->Unit(benchmark::kMillisecond);

void BM_MethodAFactorisationOnly(benchmark::State& state) {
  const recon::MethodASystem& system = recon::sharedMethodASystem();
  std::vector<recon::FeaturePoint> centres = system.interpolant().centres();
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::RbfInterpolant(centres));
}
BENCHMARK(BM_MethodAFactorisationOnly)->Unit(benchmark::kMillisecond);

void BM_MethodA_168Samples(benchmark::State& state) {
  const SliceSet slices = recon::extractSlices(truth());
  recon::sharedMethodASystem();  // built once, outside the timing
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructMethodA(slices));
}
BENCHMARK(BM_MethodA_168Samples)->Unit(benchmark::kMillisecond);

void BM_MethodAInterpolationOnly(benchmark::State& state) {
  const std::vector<recon::Subspace> measured = recon::reconstructMeasuredSubspaces(
      recon::extractSlices(truth()), false, recon::TorusRule::FundamentalSquare, "bench");
  const recon::MethodASystem& system = recon::sharedMethodASystem();
  for (auto _ : state)
    benchmark::DoNotOptimize(system.interpolate(measured));
}
BENCHMARK(BM_MethodAInterpolationOnly)->Unit(benchmark::kMillisecond);

void BM_Uniform_169Samples(benchmark::State& state) {
  const SliceSet samples = recon::extractUniformSamples(truth(), 13);
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructScattered(samples));
}
BENCHMARK(BM_Uniform_169Samples)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
