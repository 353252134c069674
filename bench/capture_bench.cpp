// The capture pipeline per 1280 x 720 frame (detection + pose + gate + sample) against the plain
// AprilTag detector on the same frame, one core: goal < 10 ms for the pipeline at 30 deg.
#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/tag36h11.h>
#include <benchmark/benchmark.h>

#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig.hpp"

namespace {

using namespace slicecap;

// An LED-on frame and its LED-off neighbour of a realistic sweep at the given elevations.
struct Frames {
  hal::Frame on, off;
  SliceId slice;
  explicit Frames(int thetaDeg) : slice{SliceKind::Axial, {thetaDeg, thetaDeg}} {
    sim::RigParams rig = sim::RigParams::realistic();
    const vision::CameraModel camera = vision::defaultSimulatedCamera();
    const vision::TargetGeometry target = vision::defaultTarget();
    const sim::FrameRenderer renderer(camera, target, sim::loadMaterial("satin-red-90"), rig);
    const auto plans = sim::planSweep(slice, 15.0, sim::RigParams::ideal(), camera, target);
    const sim::FrameScene lit{
        {plans[2].pose}, plans[2].lightMm, true, 8000.0, 1.0, std::nullopt, 7};
    sim::FrameScene dark = lit;
    dark.ledOn = false;
    on = {renderer.render(lit), PixelEncoding::Srgb8, {2, 0, 8000.0, 1.0, true}};
    off = {renderer.render(dark), PixelEncoding::Srgb8, {1, 0, 8000.0, 1.0, false}};
  }
};

const Frames& framesAt(int thetaDeg) {
  static const Frames at30(30), at75(75);
  return thetaDeg == 30 ? at30 : at75;
}

void BM_Pipeline(benchmark::State& state) {
  const Frames& f = framesAt(static_cast<int>(state.range(0)));
  capture::FramePipeline pipeline(vision::defaultTarget(), vision::defaultSimulatedCamera());
  pipeline.setAmbientFrame(f.off);
  for (auto _ : state) {
    const capture::FrameOutcome outcome = pipeline.process(f.on, f.slice);
    if (outcome.kind != capture::FrameOutcome::Kind::Sample) state.SkipWithError("not a sample");
    benchmark::DoNotOptimize(outcome);
  }
}
BENCHMARK(BM_Pipeline)->Arg(30)->Arg(75)->Unit(benchmark::kMillisecond);

// The baseline: the library alone at its defaults (quad_decimate 2) or at full resolution, on
// the gray image (the conversion is not timed).
void BM_PlainApriltag(benchmark::State& state) {
  const Frames& f = framesAt(static_cast<int>(state.range(0)));
  const Image& image = f.on.image;
  image_u8_t* gray = image_u8_create(image.width, image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      gray->buf[y * gray->stride + x] = static_cast<std::uint8_t>(
          (image.at(x, y, 0) + image.at(x, y, 1) + image.at(x, y, 2)) / 3);
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(detector, family, 1);
  detector->nthreads = 1;
  detector->quad_decimate = static_cast<float>(state.range(1));
  for (auto _ : state) {
    zarray_t* detections = apriltag_detector_detect(detector, gray);
    benchmark::DoNotOptimize(zarray_size(detections));
    apriltag_detections_destroy(detections);
  }
  apriltag_detector_destroy(detector);
  tag36h11_destroy(family);
  image_u8_destroy(gray);
}
BENCHMARK(BM_PlainApriltag)
    ->Args({30, 2})
    ->Args({30, 1})
    ->Args({75, 2})
    ->Args({75, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace
BENCHMARK_MAIN();
