// The figures behind issue 44 goal (a)'s noise floor (scripts/room-light-floor): the camera
// model's RAW stream (SRGGB10, the default sensor noise) held still at the first planned position
// of each of the 8 slices of satin-blue-45, the LED 2 frames on, 2 off at a 40 ms frame (mains_hz =
// 50), with no room light and with room light at 15 % of the LED flickering 30 % deep at 100 Hz.
// Per case the spread of the pipeline's per-frame samples against the material at their own
// directions, and what the sensor's noise alone gives the window's LED light: per pixel read
// noise^2 + value / full well, the LED-on frame's mean over the window's pixels less the two
// LED-off frames' (weights 1/3 and 2/3: 5/9 of one frame's variance). Not run unless asked: it
// takes a minute.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "../support/bracket_rig.hpp"
#include "slicecap/capture/area_reading.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/rig.hpp"
#include "slicecap/sim/rig_scene.hpp"
#include "slicecap/sim/room_light.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {
namespace {

double medianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double rmsOf(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x * x;
  return v.empty() ? 0.0 : std::sqrt(sum / double(v.size()));
}

// Each sample's relative error per channel and as an RGB vector, against the material at the
// sample's own directions.
struct SampleErrors {
  std::vector<double> rel[3], vector;
  void add(const FrameSample& s, const models::ReflectanceModel& material) {
    const Rgb t = material.evaluate(toUnitVector(s.light), toUnitVector(s.view));
    double e2 = 0.0, t2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      rel[k].push_back(s.value[k] / t[k] - 1.0);
      e2 += (s.value[k] - t[k]) * (s.value[k] - t[k]), t2 += t[k] * t[k];
    }
    vector.push_back(std::sqrt(e2 / t2));
  }
};

// The model's RAW stream (SRGGB10, the default sensor noise) with the room's 100 Hz flicker 30 %
// deep where there is room light, a share `drop` of its frames lost.
hal::SensorModel rawSensor(double roomLight, double drop) {
  hal::SensorModel model;
  model.rawFormat = hal::BayerFormat{hal::BayerOrder::Rggb, 10, hal::BayerPacking::Csi2Packed};
  model.holdSceneUntilStrobe = false;
  model.flickerHz = 100.0;
  model.flickerDepth = roomLight > 0 ? 0.3 : 0.0;
  model.dropProbability = drop;
  return model;
}

constexpr double kFramePeriodUs = 40000.0;  // mains_hz = 50

// `scene` through the model camera at `exposureUs`, 40 ms frames, the LED 2 frames on and 2 off.
struct StrobedRawCamera {
  hal::FakeClock clock{1'000'000};
  std::shared_ptr<hal::LedTimeline> led = std::make_shared<hal::LedTimeline>(true);
  std::unique_ptr<hal::ModelCamera> camera;
  StrobedRawCamera(std::shared_ptr<hal::SceneSource> scene, hal::SensorModel model,
                   double exposureUs) {
    model.realTime = false;
    for (int k = 2; k < 2000; k += 2)
      led->record(1'000'000 + std::int64_t((k + 0.97) * kFramePeriodUs), (k / 2) % 2 == 0);
    camera = std::make_unique<hal::ModelCamera>(std::move(scene), led, clock, model);
    hal::CameraConfig config;
    config.frameDurationUs = kFramePeriodUs;
    config.raw = hal::RawCapture::On;
    camera->configure(config);
    camera->start();
    EXPECT_TRUE(camera->lockExposure({exposureUs, 1.0}).locked);
  }
};

PipelineSettings floorSettings(const hal::SensorModel& model) {
  PipelineSettings settings;
  settings.noise = {model.readNoise, model.fullWellElectrons};
  settings.poseAmbientFrames = true;
  settings.windowCellsPerSide = 0;
  return settings;
}

// The camera's frames through `pipeline` as the live loop pairs them: each fully lit frame
// waits for the next fully dark one, then is processed with it as its following LED-off frame;
// `onSample(lit frame, outcome)` for each sample, until `done()` or the stream ends.
template <typename OnSample, typename Done>
void strobedSamples(hal::ModelCamera& camera, FramePipeline& pipeline, const SliceId& slice,
                    OnSample onSample, Done done) {
  std::vector<hal::Frame> held;
  for (int n = 0; n < 4000 && !done(); ++n) {
    hal::CaptureResult r = camera.nextFrame(std::chrono::milliseconds(1000));
    if (r.status == hal::CaptureResult::Status::EndOfStream) break;
    if (!r.frame || r.frame->metadata.exposureLocks < 1) continue;
    hal::Frame f = std::move(*r.frame);
    const auto truth = camera.truth(f.metadata.sequence);
    const auto [lo, hi] =
        std::minmax_element(truth->rowOnFraction.begin(), truth->rowOnFraction.end());
    if (*hi < 1e-3) {
      f.metadata.ledOn = false;
      for (const hal::Frame& on : held) {
        pipeline.setFollowingAmbientFrame(f);
        const FrameOutcome o = pipeline.process(on, slice);
        if (o.kind == FrameOutcome::Kind::Sample) onSample(on, o);
      }
      held.clear();
      pipeline.process(f, slice);
    } else if (*lo > 1.0 - 1e-3) {
      f.metadata.ledOn = true;
      held.push_back(std::move(f));
    }
  }
}

struct Spread {
  Rgb measuredRms, expectedRms;  // relative, per channel
  double medianVectorError = 0.0;
  double expectedVectorRms = 0.0;
  int samples = 0;
};

Spread measure(const SliceId& slice, double roomLight, int wanted) {
  sim::RigParams rig = sim::RigParams::steady();
  rig.framesPerSlice = 32;
  rig.ambientIrradiance = sim::roomIrradianceFor(rig, roomLight);
  const auto material = sim::loadMaterial("satin-blue-45");
  const vision::CameraModel cameraModel = vision::defaultSimulatedCamera();
  const auto renderer =
      std::make_shared<sim::FrameRenderer>(cameraModel, vision::defaultTarget(), material, rig);
  const sim::FramePlan plan =
      sim::planSweep(slice, kAxialOffsetDeg, rig, cameraModel, renderer->target()).front();
  const vision::Pose pose = plan.exposurePoses.front();
  const auto scene = std::make_shared<test::StillScene>(renderer, pose, plan.lightMm);
  const hal::SensorModel model = rawSensor(roomLight, 0.0);
  const double exposureUs = test::BracketRig(scene, model).meteredExposureUs();
  StrobedRawCamera strobed(scene, model, exposureUs);
  const PipelineSettings settings = floorSettings(model);
  FramePipeline pipeline(renderer->target(), cameraModel, settings);

  // The sensor's noise on the window's LED light, from the scene's light and the pixel count.
  const vision::RectMm& w = renderer->target().window;
  const double half = settings.windowSampleFraction * std::min(w.widthMm(), w.heightMm()) / 2.0;
  const vision::PointMm c = w.centre();
  const AreaSpec windowSpec{{c.xMm - half, c.yMm - half, c.xMm + half, c.yMm + half}, 0.0, 2.0};
  const sim::FrameScene lit{{pose}, plan.lightMm, true, 1e6, 1.0, std::nullopt, 0};
  sim::FrameScene dark = lit;
  dark.ledOn = false;
  const Rgb room = renderer->windowPoint(dark, {0, 0, 0}).expectedLinear * (exposureUs * 1e-6);
  const Rgb ledLight =
      renderer->windowPoint(lit, {0, 0, 0}).expectedLinear * (exposureUs * 1e-6) - room;

  Spread spread;
  SampleErrors errors;
  int pixels = 0;
  strobedSamples(
      *strobed.camera, pipeline, slice,
      [&](const hal::Frame& on, const FrameOutcome& o) {
        errors.add(*o.sample, *material);
        ++spread.samples;
        if (!pixels)
          pixels = readArea(on, pose, cameraModel, windowSpec, settings.noise,
                            CodeTable::srgb()).pixels;
      },
      [&] { return spread.samples >= wanted; });
  const double read2 = model.readNoise * model.readNoise;
  double vectorVariance = 0.0, ledNorm2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    // A decoded pixel's green is the mean of the cell's two (hal::decodeBayer).
    const double cells = k == 1 ? 2.0 : 1.0;
    const double on = (read2 + (room[k] + ledLight[k]) / model.fullWellElectrons) / cells;
    const double off = (read2 + room[k] / model.fullWellElectrons) / cells;
    const double variance = (on + 5.0 / 9.0 * off) / std::max(pixels, 1);
    spread.measuredRms[k] = rmsOf(errors.rel[k]);
    spread.expectedRms[k] = std::sqrt(variance) / ledLight[k];
    vectorVariance += variance, ledNorm2 += ledLight[k] * ledLight[k];
  }
  spread.medianVectorError = medianOf(errors.vector);
  spread.expectedVectorRms = std::sqrt(vectorVariance / ledNorm2);
  std::printf("[ %s room %.2f ] exposure %.0f us, window %d px, LED light %.4f %.4f %.4f, room "
              "light %.4f %.4f %.4f of full scale\n",
              toString(slice).c_str(), roomLight, exposureUs, pixels, ledLight[0], ledLight[1],
              ledLight[2], room[0], room[1], room[2]);
  return spread;
}

TEST(RoomLightFloor, SampleSpreadWithAndWithoutRoomLight) {
  if (!std::getenv("SLICECAP_ROOM_LIGHT_FLOOR"))
    GTEST_SKIP() << "SLICECAP_ROOM_LIGHT_FLOOR not set (scripts/room-light-floor sets it)";
  const int wanted = 16;
  for (const SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal})
    for (const auto& [ti, tv] : {std::pair{30, 30}, {30, 75}, {75, 30}, {75, 75}}) {
      const SliceId slice{kind, {ti, tv}};
      const Spread darkRoom = measure(slice, 0.0, wanted), litRoom = measure(slice, 0.15, wanted);
      std::printf("[ %s ] per-frame rms R/G/B: dark %.2f/%.2f/%.2f %% (sensor alone %.2f/%.2f/%.2f "
                  "%%), room %.2f/%.2f/%.2f %% (sensor alone %.2f/%.2f/%.2f %%); median vector "
                  "error dark %.2f %%, room %.2f %% (%.2f x); sensor alone rms %.2f %% vs %.2f %% "
                  "(%.2f x); %d, %d samples\n",
                  toString(slice).c_str(), 100 * darkRoom.measuredRms[0],
                  100 * darkRoom.measuredRms[1], 100 * darkRoom.measuredRms[2],
                  100 * darkRoom.expectedRms[0], 100 * darkRoom.expectedRms[1],
                  100 * darkRoom.expectedRms[2], 100 * litRoom.measuredRms[0],
                  100 * litRoom.measuredRms[1], 100 * litRoom.measuredRms[2],
                  100 * litRoom.expectedRms[0], 100 * litRoom.expectedRms[1],
                  100 * litRoom.expectedRms[2], 100 * darkRoom.medianVectorError,
                  100 * litRoom.medianVectorError,
                  litRoom.medianVectorError / darkRoom.medianVectorError,
                  100 * darkRoom.expectedVectorRms, 100 * litRoom.expectedVectorRms,
                  litRoom.expectedVectorRms / darkRoom.expectedVectorRms, darkRoom.samples,
                  litRoom.samples);
    }
}

// The per-frame samples of the steady rig's axial 75/30 sweep (32 positions over 8 s), the LED 2
// on, 2 off, a share `drop` of the frames lost: the median signed error of each channel and the
// median vector error.
void movingSweep(double roomLight, double drop) {
  sim::RigParams rig = sim::RigParams::steady();
  rig.framesPerSlice = 32;  // slicecapd's model_positions and model_sweep_seconds
  rig.sweepSeconds = 8;
  rig.ambientIrradiance = sim::roomIrradianceFor(rig, roomLight);
  const auto material = sim::loadMaterial("satin-blue-45");
  const vision::CameraModel cameraModel = vision::defaultSimulatedCamera();
  const auto renderer =
      std::make_shared<sim::FrameRenderer>(cameraModel, vision::defaultTarget(), material, rig);
  const SliceId slice{SliceKind::Axial, {75, 30}};
  const auto scene = std::make_shared<sim::RigScene>(renderer, slice, rig);
  const hal::SensorModel model = rawSensor(roomLight, drop);
  const sim::FramePlan& first = scene->plans().front();
  const double exposureUs =
      test::BracketRig(std::make_shared<test::StillScene>(renderer, first.exposurePoses.front(),
                                                          first.lightMm),
                       model)
          .meteredExposureUs();
  StrobedRawCamera strobed(scene, model, exposureUs);
  FramePipeline pipeline(renderer->target(), cameraModel, floorSettings(model));
  SampleErrors errors;
  strobedSamples(
      *strobed.camera, pipeline, slice,
      [&](const hal::Frame& on, const FrameOutcome& o) {
        errors.add(*o.sample, *material);
        if (!std::getenv("SLICECAP_ROOM_LIGHT_FLOOR_SAMPLES")) return;
        // How far apart the camera was at the two LED-off frames (0: one frame, or one place).
        const auto terms = pipeline.ambientTermsFor(on.metadata.timestampUs, o.measurement.pose);
        double apartMm = 0.0;
        if (terms.size() == 2 && terms[0].pose && terms[1].pose)
          apartMm = (terms[0].pose->cameraCentreMm() - terms[1].pose->cameraCentreMm()).norm();
        std::printf("[ sample ] LED-off frames %.1f mm apart: error %.2f %%\n", apartMm,
                    100 * errors.vector.back());
      },
      [] { return false; });
  std::printf("[ moving %s room %.2f, %.0f %% of frames dropped ] median signed R/G/B %+.2f/%+.2f/"
              "%+.2f %%, median vector error %.2f %% (%zu samples, %llu frames dropped)\n",
              toString(slice).c_str(), roomLight, 100 * drop, 100 * medianOf(errors.rel[0]),
              100 * medianOf(errors.rel[1]), 100 * medianOf(errors.rel[2]),
              100 * medianOf(errors.vector), errors.vector.size(),
              static_cast<unsigned long long>(strobed.camera->framesDropped()));
}

TEST(RoomLightFloor, TheMovingRigWithAndWithoutDroppedFrames) {
  if (!std::getenv("SLICECAP_ROOM_LIGHT_FLOOR"))
    GTEST_SKIP() << "SLICECAP_ROOM_LIGHT_FLOOR not set (scripts/room-light-floor sets it)";
  for (const double drop : {0.0, 0.7})
    for (const double room : {0.0, 0.15}) movingSweep(room, drop);
}

}  // namespace
}  // namespace slicecap::capture
