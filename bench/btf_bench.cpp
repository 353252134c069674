// BTF reconstruction speed: a 128 x 128 texture of the woven material, every texel through Method
// B (goal: < 10 s on the two cores of the development machine; paper: 4.5 h on three), with 1 and
// 2 threads, Method A with its one shared factorisation, and the learned prior. Reports the
// process's peak RSS.
// Also what texture capture costs the daemon per kept frame: rectifying a 1280 x 720 sRGB frame's
// window to N x N texels (with its LED-off frame subtracted), and storing it (synced write).
// Run it directly (build/bench/btf_bench) for the two-thread figure: scripts/bench pins one core.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <filesystem>

#include "slicecap/btf/btf_reconstruction.hpp"
#include "slicecap/btf/rectifier.hpp"
#include "slicecap/btf/texture_store.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_extraction.hpp"
#include "slicecap/sim/patterned_material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/simulate.hpp"
#include "slicecap/vision/target.hpp"

namespace {

using namespace slicecap;

Eigen::Vector3d pointAt(double distanceMm, double thetaDeg, double phiDeg) {
  const UnitVector u = toUnitVector({thetaDeg, phiDeg});
  return distanceMm * Eigen::Vector3d(u.x, u.y, u.z);
}

// What an ideal capture of the woven material at 300 mm leaves in the texture bins: per slice
// and 15 deg bin the camera and LED positions, and per texel its material's table value there.
std::vector<btf::SliceTexture> wovenCapture(const btf::TextureGrid& grid) {
  const auto woven = sim::makeWovenMaterial(10.0);
  const Abrdf tables[2] = {models::tabulate(woven->component(0)),
                           models::tabulate(woven->component(1))};
  std::vector<btf::SliceTexture> slices;
  for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
    for (const ElevationPair& pair : kMeasuredPairs) {
      btf::SliceTexture slice{{kind, pair}, std::vector<btf::TextureBin>(24)};
      for (int k = 0; k < 24; ++k) {
        const AzimuthPair phi = slicePoint(kind, k * 15.0);
        btf::TextureBin& bin = slice.bins[std::size_t(k)];
        bin.frames = 1;
        bin.cameraMm = pointAt(300.0, pair.thetaVDeg, phi.phiVDeg);
        bin.lightMm = pointAt(300.0, pair.thetaIDeg, phi.phiIDeg);
        const Rgb values[2] = {recon::sampleTable(tables[0], pair, phi),
                               recon::sampleTable(tables[1], pair, phi)};
        bin.texels.resize(grid.texelCount() * 3);
        for (int row = 0; row < grid.resolution(); ++row)
          for (int column = 0; column < grid.resolution(); ++column) {
            const Eigen::Vector3d p = grid.texelCentreMm(column, row);
            const Rgb& v = values[woven->firstWeightAt(p.x(), p.y()) > 0.5 ? 0 : 1];
            for (int c = 0; c < 3; ++c)
              bin.texels[3 * grid.index(column, row) + std::size_t(c)] = static_cast<float>(v[c]);
          }
      }
      slices.push_back(std::move(slice));
    }
  }
  return slices;
}

// CPU seconds of the whole process (every thread), user + system.
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Peak RSS, and the CPU seconds the timed loop took over all threads: on a shared machine the
// wall time depends on the load, while CPU seconds / threads is the wall time on idle cores.
void reportPeakRssAndCpu(benchmark::State& state, double cpuBefore) {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["peak_rss_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
  state.counters["cpu_s_all_threads"] = processCpuSeconds() - cpuBefore;
}

void BM_Btf128_MethodB(benchmark::State& state) {
  const btf::TextureGrid grid(128, vision::defaultTarget().window);
  const std::vector<btf::SliceTexture> slices = wovenCapture(grid);
  btf::BtfReconstructionParams params;
  params.threads = static_cast<int>(state.range(0));
  const double cpuBefore = processCpuSeconds();
  for (auto _ : state)
    benchmark::DoNotOptimize(btf::reconstructBtf(grid, slices, params));
  state.counters["texels"] = static_cast<double>(grid.texelCount());
  reportPeakRssAndCpu(state, cpuBefore);
}
BENCHMARK(BM_Btf128_MethodB)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

// One texel: its slice samples at its own directions, then Method B (where the time goes).
void BM_OneTexel_MethodB(benchmark::State& state) {
  const btf::TextureGrid grid(8, vision::defaultTarget().window);
  const std::vector<btf::SliceTexture> slices = wovenCapture(grid);
  for (auto _ : state)
    benchmark::DoNotOptimize(recon::reconstructMethodB(btf::texelSlices(grid, slices, 3, 4)));
}
BENCHMARK(BM_OneTexel_MethodB)->Unit(benchmark::kMicrosecond);

void BM_OneTexel_SliceSamples(benchmark::State& state) {
  const btf::TextureGrid grid(8, vision::defaultTarget().window);
  const std::vector<btf::SliceTexture> slices = wovenCapture(grid);
  for (auto _ : state)
    benchmark::DoNotOptimize(btf::texelSlices(grid, slices, 3, 4));
}
BENCHMARK(BM_OneTexel_SliceSamples)->Unit(benchmark::kMicrosecond);

void BM_Btf128_MethodA(benchmark::State& state) {
  const btf::TextureGrid grid(128, vision::defaultTarget().window);
  const std::vector<btf::SliceTexture> slices = wovenCapture(grid);
  btf::BtfReconstructionParams params;
  params.method = methods::MethodId::A;
  params.threads = static_cast<int>(state.range(0));
  const double cpuBefore = processCpuSeconds();
  for (auto _ : state)
    benchmark::DoNotOptimize(btf::reconstructBtf(grid, slices, params));
  reportPeakRssAndCpu(state, cpuBefore);
}
BENCHMARK(BM_Btf128_MethodA)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// The learned prior per texel (`slicecap btf --method prior`): the shipped model.
void BM_Btf128_Prior(benchmark::State& state) {
  const btf::TextureGrid grid(128, vision::defaultTarget().window);
  const std::vector<btf::SliceTexture> slices = wovenCapture(grid);
  btf::BtfReconstructionParams params;
  params.method = methods::MethodId::Prior;
  params.priorModel = &prior::defaultPriorModel();
  params.threads = static_cast<int>(state.range(0));
  const double cpuBefore = processCpuSeconds();
  for (auto _ : state)
    benchmark::DoNotOptimize(btf::reconstructBtf(grid, slices, params));
  reportPeakRssAndCpu(state, cpuBefore);
}
BENCHMARK(BM_Btf128_Prior)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_OneTexel_Prior(benchmark::State& state) {
  const btf::TextureGrid grid(8, vision::defaultTarget().window);
  const std::vector<btf::SliceTexture> slices = wovenCapture(grid);
  // As reconstructBtf runs it: one PriorReconstructor (the basis entry by entry) for every texel.
  const prior::PriorReconstructor reconstructor(prior::defaultPriorModel());
  for (auto _ : state)
    benchmark::DoNotOptimize(reconstructor.reconstruct(btf::texelSlices(grid, slices, 3, 4)));
}
BENCHMARK(BM_OneTexel_Prior)->Unit(benchmark::kMicrosecond);

// One 1280 x 720 8-bit sRGB frame of the woven material (axial 30/30) with its true pose and LED.
struct RenderedFrame {
  hal::Frame frame;
  vision::CameraModel camera;
  vision::RectMm window;
  btf::FrameGeometry geometry;
};

const RenderedFrame& renderedFrame() {
  static const RenderedFrame rendered = [] {
    sim::RigParams rig = sim::RigParams::ideal();
    rig.framesPerSlice = 8;
    const sim::FrameRenderer renderer(vision::defaultSimulatedCamera(), vision::defaultTarget(),
                                      sim::makeWovenMaterial(10.0), rig);
    std::vector<sim::FramePlan> plans =
        sim::planSweep({SliceKind::Axial, {30, 30}}, kAxialOffsetDeg, rig, renderer.camera(),
                       renderer.target());
    const sim::FramePlan& plan = plans[1];
    sim::FrameScene scene;
    scene.exposurePoses = plan.exposurePoses;
    scene.lightMm = plan.lightMm;
    scene.exposureUs = std::round(sim::chooseExposureUs(renderer, rig, plans));
    scene.gain = plan.gain;
    hal::Frame frame{renderer.render(scene), rig.encoding, {}};
    frame.metadata = {1, plan.timestampUs, scene.exposureUs, plan.gain, true};
    const capture::PointLight light{{plan.lightMm.x(), plan.lightMm.y(), plan.lightMm.z()},
                                    Rgb::gray(rig.sensorResponse * rig.ledIntensityWPerSr)};
    return RenderedFrame{std::move(frame), renderer.camera(), renderer.target().window,
                         {plan.pose, light}};
  }();
  return rendered;
}

// Rectification of a kept frame at N x N texels, the LED-off frame (here the same image) read at
// the same pixels as live: the CPU a kept frame costs the daemon's frame loop.
void BM_RectifyFrame(benchmark::State& state) {
  const RenderedFrame& r = renderedFrame();
  const btf::TextureGrid grid(static_cast<int>(state.range(0)), r.window);
  const capture::AmbientTerm ambient{&r.frame, std::nullopt, 1.0};
  for (auto _ : state)
    benchmark::DoNotOptimize(btf::rectifyFrame(grid, r.camera, r.frame, {&ambient, 1}, r.geometry));
}
BENCHMARK(BM_RectifyFrame)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);

// Storing a kept N x N frame: half floats, CRC, temporary, fsync, rename, folder fsync. Depends on
// the disk (an SD card is slower than this machine's): a budget, not a constant.
void BM_StoreKeptFrame(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / "slicecap-btf-bench-store";
  std::filesystem::remove_all(directory);
  btf::TextureStore store = btf::TextureStore::openOrCreate(directory, {n, {-20, -20, 20, 20}, 1});
  btf::TextureFrame frame{0.0, {0, 0, 300}, {0, 100, 280},
                          std::vector<float>(std::size_t(n) * n * 3, 0.25f)};
  const SliceId slice{SliceKind::Axial, {30, 30}};
  double parameterDeg = 7.0;
  for (auto _ : state) {
    // Each frame nearer its bin's centre than the last: always kept, replacing the one before.
    frame.sliceParameterDeg = parameterDeg;
    parameterDeg *= 0.999;
    benchmark::DoNotOptimize(store.add(slice, frame));
  }
  std::filesystem::remove_all(directory);
}
BENCHMARK(BM_StoreKeptFrame)->Arg(128)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
