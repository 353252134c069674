// The model camera's cost per frame on the thread that takes it: a 1280 x 720 frame exposed
// against the LED's timeline, with noise, colour gains and the tone curve (the processed stream)
// or through the RAW mosaic and its decoder. The daemon's frame loop pays this on top of the
// capture pipeline when it runs on `camera = model`; a real camera's ISP does it in parallel, so
// the less it costs, the closer the loop's timing is to the box's (budget: well under the 33 ms
// frame period, so the loop keeps up with 30 fps with the pipeline's ~10 ms beside it).
#include <benchmark/benchmark.h>

#include <memory>

#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/hal/model_camera.hpp"

namespace {

using namespace slicecap;

constexpr int kWidth = 1280, kHeight = 720;

// A still scene: room light and LED light over a gradient, so samples span the tone curve.
class GradientScene final : public hal::SceneSource {
 public:
  GradientScene() : light_(std::make_shared<hal::SceneLight>()) {
    light_->widthPx = kWidth;
    light_->heightPx = kHeight;
    const std::size_t values = std::size_t(kWidth) * kHeight * 3;
    light_->ambientRate.resize(values);
    light_->ledRate.resize(values);
    for (std::size_t i = 0; i < values; ++i) {
      light_->ambientRate[i] = 20.0f + float(i % 997) * 0.05f;
      light_->ledRate[i] = 100.0f + float(i % 1223) * 0.4f;
    }
  }
  std::string id() const override { return "gradient"; }
  std::shared_ptr<const hal::SceneLight> lightAt(std::int64_t) override { return light_; }

 private:
  std::shared_ptr<hal::SceneLight> light_;
};

void runFrames(benchmark::State& state, bool raw) {
  hal::SensorModel model;
  model.realTime = false;
  model.holdSceneUntilStrobe = false;
  if (raw) model.rawFormat = hal::BayerFormat{hal::BayerOrder::Rggb, 10, hal::BayerPacking::Csi2Packed};
  hal::FakeClock clock(1'000'000);
  // The LED on for half of each frame, so every row's exposure is split between the two lights.
  auto led = std::make_shared<hal::LedTimeline>();
  for (int k = 0; k < 20000; ++k) led->record(1'000'000 + k * 16'667, k % 2 == 0);
  hal::ModelCamera camera(std::make_shared<GradientScene>(), led, clock, model);
  hal::CameraConfig config;
  config.widthPx = kWidth;
  config.heightPx = kHeight;
  config.exposureUs = 8000.0;
  camera.configure(config);
  camera.start();
  for (auto _ : state) {
    hal::CaptureResult result = camera.nextFrame(std::chrono::milliseconds(1000));
    if (result.status != hal::CaptureResult::Status::Frame) {
      state.SkipWithError("the model camera delivered no frame");
      break;
    }
    benchmark::DoNotOptimize(result.frame->image.samples.data());
  }
}

void BM_ModelCameraFrame_Srgb8(benchmark::State& state) { runFrames(state, false); }
BENCHMARK(BM_ModelCameraFrame_Srgb8)->Unit(benchmark::kMillisecond);

void BM_ModelCameraFrame_Raw10(benchmark::State& state) { runFrames(state, true); }
BENCHMARK(BM_ModelCameraFrame_Raw10)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
