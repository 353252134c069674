// Virtual-rig rendering speed: one 1280 x 720 frame on one core; goal < 20 ms, so a full session
// (8 x 48 frames) renders in well under a minute. Encoding and PNG writing are timed apart.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "slicecap/io/png_image.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig.hpp"

namespace {

using namespace slicecap;

struct Fixture {
  sim::RigParams rig;
  std::unique_ptr<sim::FrameRenderer> renderer;
  sim::FrameScene scene;
  sim::FrameScene blurred;

  Fixture(const std::string& material, PixelEncoding encoding, bool noisy) {
    rig = noisy ? sim::RigParams::realistic() : sim::RigParams::ideal();
    rig.encoding = encoding;
    const vision::CameraModel camera = vision::defaultSimulatedCamera();
    const vision::TargetGeometry target = vision::defaultTarget();
    renderer =
        std::make_unique<sim::FrameRenderer>(camera, target, sim::loadMaterial(material), rig);
    const auto plans =
        sim::planSweep({SliceKind::Axial, {30, 30}}, 15.0, sim::RigParams::ideal(), camera, target);
    scene = {{plans[3].pose}, plans[3].lightMm, true, 8000.0, 1.0, std::nullopt, 7};
    blurred = scene;
    blurred.exposurePoses = {plans[3].pose, plans[3].pose, plans[3].pose, plans[3].pose};
  }
};

void BM_RenderFrame_Srgb8_Noisy_Ward(benchmark::State& state) {
  Fixture f("satin-blue-45", PixelEncoding::Srgb8, true);
  for (auto _ : state)
    benchmark::DoNotOptimize(f.renderer->render(f.scene));
}
BENCHMARK(BM_RenderFrame_Srgb8_Noisy_Ward)->Unit(benchmark::kMillisecond);

void BM_RenderFrame_Linear16_NoiseFree_Ggx(benchmark::State& state) {
  Fixture f("brushed-aluminium", PixelEncoding::Linear16, false);
  for (auto _ : state)
    benchmark::DoNotOptimize(f.renderer->render(f.scene));
}
BENCHMARK(BM_RenderFrame_Linear16_NoiseFree_Ggx)->Unit(benchmark::kMillisecond);

void BM_RenderFrame_Srgb8_Noisy_Table(benchmark::State& state) {
  Fixture f("ggx:diffuse=0.1,f0=0.8,ax=0.2,ay=0.4", PixelEncoding::Srgb8, true);
  // The same model tabulated: a table material costs one grid interpolation per BRDF node.
  f.renderer = std::make_unique<sim::FrameRenderer>(
      vision::defaultSimulatedCamera(), vision::defaultTarget(),
      sim::makeTableMaterial(models::tabulate(f.renderer->material()), "bench"), f.rig);
  for (auto _ : state)
    benchmark::DoNotOptimize(f.renderer->render(f.scene));
}
BENCHMARK(BM_RenderFrame_Srgb8_Noisy_Table)->Unit(benchmark::kMillisecond);

void BM_RenderFrame_MotionBlur4(benchmark::State& state) {
  Fixture f("satin-blue-45", PixelEncoding::Srgb8, true);
  for (auto _ : state)
    benchmark::DoNotOptimize(f.renderer->render(f.blurred));
}
BENCHMARK(BM_RenderFrame_MotionBlur4)->Unit(benchmark::kMillisecond);

void BM_WritePngFrame_Srgb8_Noisy(benchmark::State& state) {
  Fixture f("satin-blue-45", PixelEncoding::Srgb8, true);
  const Image image = f.renderer->render(f.scene);
  const auto path = std::filesystem::temp_directory_path() / "slicecap-bench-frame.png";
  for (auto _ : state)
    io::writePng(path, image);
  std::filesystem::remove(path);
}
BENCHMARK(BM_WritePngFrame_Srgb8_Noisy)->Unit(benchmark::kMillisecond);

}  // namespace
BENCHMARK_MAIN();
