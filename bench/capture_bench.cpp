// The capture pipeline per 1280 x 720 frame (detection + pose + gate + sample) against the plain
// AprilTag detector on the same frame, one core: goal < 10 ms for the pipeline at 30 deg.
#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/tag36h11.h>
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <map>
#include <string>

#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig.hpp"
#include "slicecap/sim/simulate.hpp"

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

// Second argument: the window's cells per side (0: none, the pipeline before issue 45; 8: the
// default), so one run gives the cells' cost as a ratio.
void BM_Pipeline(benchmark::State& state) {
  const Frames& f = framesAt(static_cast<int>(state.range(0)));
  capture::PipelineSettings settings;
  settings.windowCellsPerSide = static_cast<int>(state.range(1));
  capture::FramePipeline pipeline(vision::defaultTarget(), vision::defaultSimulatedCamera(),
                                  settings);
  pipeline.setAmbientFrame(f.off);
  for (auto _ : state) {
    const capture::FrameOutcome outcome = pipeline.process(f.on, f.slice);
    if (outcome.kind != capture::FrameOutcome::Kind::Sample) state.SkipWithError("not a sample");
    benchmark::DoNotOptimize(outcome);
  }
}
BENCHMARK(BM_Pipeline)
    ->Args({30, 0})
    ->Args({30, 8})
    ->Args({75, 0})
    ->Args({75, 8})
    ->Unit(benchmark::kMillisecond);

// The baseline: the plain library, single-threaded tag36h11 at a given quad_decimate, on the
// mean of an 8-bit RGB frame's channels (the conversion is not timed).
struct PlainDetector {
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  explicit PlainDetector(float decimation) {
    apriltag_detector_add_family_bits(detector, family, 1);
    detector->nthreads = 1;
    detector->quad_decimate = decimation;
  }
  ~PlainDetector() {
    apriltag_detector_destroy(detector);
    tag36h11_destroy(family);
  }
  PlainDetector(const PlainDetector&) = delete;
  PlainDetector& operator=(const PlainDetector&) = delete;
  void detect(image_u8_t* gray) {
    zarray_t* detections = apriltag_detector_detect(detector, gray);
    benchmark::DoNotOptimize(zarray_size(detections));
    apriltag_detections_destroy(detections);
  }
};

image_u8_t* meanGray(const Image& image) {
  image_u8_t* gray = image_u8_create(image.width, image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      gray->buf[y * gray->stride + x] = static_cast<std::uint8_t>(
          (image.at(x, y, 0) + image.at(x, y, 1) + image.at(x, y, 2)) / 3);
  return gray;
}

// At the library's default (quad_decimate 2) and at full resolution.
void BM_PlainApriltag(benchmark::State& state) {
  const Frames& f = framesAt(static_cast<int>(state.range(0)));
  image_u8_t* gray = meanGray(f.on.image);
  PlainDetector plain(static_cast<float>(state.range(1)));
  for (auto _ : state)
    plain.detect(gray);
  image_u8_destroy(gray);
}
BENCHMARK(BM_PlainApriltag)
    ->Args({30, 2})
    ->Args({30, 1})
    ->Args({75, 2})
    ->Args({75, 1})
    ->Unit(benchmark::kMillisecond);

// A whole realistic sweep (48 frames, hand-held jitter, blur, occlusion, markers out of view), in
// capture order so the tracking works as it does live: per LED-on frame the median and 95th
// percentile time, the view-angle error against the truth (median, 95th percentile), and the plain
// library (decimation 2, whole frame) on the same frames. The figures the goals name.
struct Sweep {
  SliceId slice;
  io::Recording recording;
  std::vector<hal::Frame> frames;
  sim::SweepTruth truth;
  explicit Sweep(const SliceId& id) : slice(id) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("slicecap-capture-bench-" + std::to_string(::getpid())) /
                     folderName(id);
    std::filesystem::remove_all(dir);
    sim::SweepSetup setup;
    setup.rig = sim::RigParams::realistic();
    setup.materialSpec = "satin-red-90";
    const sim::FrameRenderer renderer(setup.camera, setup.target,
                                      sim::loadMaterial(setup.materialSpec), setup.rig);
    truth = sim::simulateSweep(dir, {id, kAxialOffsetDeg}, renderer, setup);
    recording = io::readRecording(dir);
    for (std::size_t i = 0; i < recording.frames.size(); ++i) {
      const io::RecordedFrame& entry = recording.frames[i];
      frames.push_back({io::readPng(io::framePath(dir, entry)),
                        recording.encoding,
                        {i, entry.timestampUs, entry.exposureUs, entry.gain, entry.ledOn}});
    }
    std::filesystem::remove_all(dir.parent_path());
  }
};

const Sweep& sweepAt(int thetaDeg) {
  static const Sweep at30({SliceKind::Axial, {30, 30}}), at75({SliceKind::Axial, {75, 75}});
  return thetaDeg == 30 ? at30 : at75;
}

// This thread's CPU time, ms: on a shared machine wall time also counts other programs' turns.
double threadCpuMs() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(std::lround(q * static_cast<double>(values.size() - 1)))];
}

// Per LED-on frame (the figures) and over every frame (the LED-off ones search too while
// the target is lost), wall and this thread's CPU time; the rejections by reason; with
// SLICECAP_BENCH_FRAMES=1 in the environment, each frame of the last iteration on stderr (its
// time, outcome, markers and tracked scale: which path a slow frame took).
void BM_PipelineSweep(benchmark::State& state) {
  const Sweep& sweep = sweepAt(static_cast<int>(state.range(0)));
  const bool listFrames = std::getenv("SLICECAP_BENCH_FRAMES") != nullptr;
  std::vector<double> frameMs, frameCpuMs, anyFrameMs, viewErrorDeg;
  std::map<std::string, int> rejections;
  int samples = 0, ledOnFrames = 0;
  std::string frameList;
  for (auto _ : state) {
    capture::FramePipeline pipeline(sweep.recording.target, sweep.recording.camera);
    frameMs.clear();
    frameCpuMs.clear();
    anyFrameMs.clear();
    viewErrorDeg.clear();
    rejections.clear();
    frameList.clear();
    samples = ledOnFrames = 0;
    for (std::size_t i = 0; i < sweep.frames.size(); ++i) {
      const double cpuStart = threadCpuMs();
      const auto start = std::chrono::steady_clock::now();
      const capture::FrameOutcome outcome = pipeline.process(sweep.frames[i], sweep.slice);
      const std::chrono::duration<double, std::milli> took =
          std::chrono::steady_clock::now() - start;
      const double cpuMs = threadCpuMs() - cpuStart;
      anyFrameMs.push_back(took.count());
      if (listFrames) {
        const auto& scale = outcome.measurement.trackedScale;
        const std::string what =
            outcome.kind == capture::FrameOutcome::Kind::Rejected
                ? std::string(toString(outcome.rejectReason))
            : outcome.kind == capture::FrameOutcome::Kind::Sample ? "sample"
                                                                  : "ambient";
        const std::string how = scale ? " tracked dec " + std::to_string(scale->quadDecimate) +
                                            " bin " + std::to_string(scale->binX) + "x" +
                                            std::to_string(scale->binY)
                                      : std::string(" untracked");
        frameList += "frame " + std::to_string(i) +
                     (sweep.frames[i].metadata.ledOn ? " on " : " off ") +
                     std::to_string(took.count()) + " ms (cpu " + std::to_string(cpuMs) + ") " +
                     what + " markers " + std::to_string(outcome.measurement.markerCount) + how +
                     "\n";
      }
      if (!sweep.frames[i].metadata.ledOn) continue;
      ++ledOnFrames;
      frameMs.push_back(took.count());
      frameCpuMs.push_back(cpuMs);
      if (outcome.kind == capture::FrameOutcome::Kind::Rejected) ++rejections[std::string(toString(outcome.rejectReason))];
      if (outcome.kind != capture::FrameOutcome::Kind::Sample) continue;
      ++samples;
      viewErrorDeg.push_back(angleBetweenDeg(outcome.sample->view, sweep.truth.frames[i].view));
    }
  }
  if (listFrames)
    std::fputs(("BM_PipelineSweep/" + std::to_string(state.range(0)) + ":\n" + frameList).c_str(),
               stderr);
  state.counters["frame_ms_median"] = percentile(frameMs, 0.5);
  state.counters["frame_ms_p95"] = percentile(frameMs, 0.95);
  state.counters["frame_ms_max"] = percentile(frameMs, 1.0);
  state.counters["frame_cpu_ms_median"] = percentile(frameCpuMs, 0.5);
  state.counters["frame_cpu_ms_p95"] = percentile(frameCpuMs, 0.95);
  state.counters["any_frame_ms_p95"] = percentile(anyFrameMs, 0.95);
  state.counters["any_frame_ms_max"] = percentile(anyFrameMs, 1.0);
  for (const auto& [reason, count] : rejections)
    state.counters["rejected_" + reason] = count;
  state.counters["view_err_deg_median"] = percentile(viewErrorDeg, 0.5);
  state.counters["view_err_deg_p95"] = percentile(viewErrorDeg, 0.95);
  state.counters["samples"] = samples;
  state.counters["led_on_frames"] = ledOnFrames;
}
BENCHMARK(BM_PipelineSweep)->Arg(30)->Arg(75)->Unit(benchmark::kMillisecond)->Iterations(3);

// The sweeps are 8-bit sRGB RGB (the realistic rig's default).
void BM_PlainApriltagSweep(benchmark::State& state) {
  const Sweep& sweep = sweepAt(static_cast<int>(state.range(0)));
  std::vector<image_u8_t*> grays;
  for (const hal::Frame& frame : sweep.frames)
    if (frame.metadata.ledOn) grays.push_back(meanGray(frame.image));
  PlainDetector plain(2.0f);
  std::vector<double> frameMs, frameCpuMs;
  for (auto _ : state) {
    frameMs.clear();
    frameCpuMs.clear();
    for (image_u8_t* gray : grays) {
      const double cpuStart = threadCpuMs();
      const auto start = std::chrono::steady_clock::now();
      plain.detect(gray);
      frameMs.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
      frameCpuMs.push_back(threadCpuMs() - cpuStart);
    }
  }
  state.counters["frame_ms_median"] = percentile(frameMs, 0.5);
  state.counters["frame_ms_p95"] = percentile(frameMs, 0.95);
  state.counters["frame_cpu_ms_median"] = percentile(frameCpuMs, 0.5);
  state.counters["frame_cpu_ms_p95"] = percentile(frameCpuMs, 0.95);
  for (image_u8_t* gray : grays)
    image_u8_destroy(gray);
}
BENCHMARK(BM_PlainApriltagSweep)->Arg(30)->Arg(75)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
BENCHMARK_MAIN();
