// runHardwareCheck on the camera model, where every answer is known: the configured readout,
// LED delay, delivery latency, control delay and tone curve must come back (issue 27's goal:
// within 10 %); and on cameras that cannot answer (no target, no timestamps).
#include "slicecap/hwcheck/hardware_check.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "../support/bracket_rig.hpp"
#include "../support/plain_led.hpp"
#include "../support/test_support.hpp"
#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/file_camera.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/hwcheck/response_check.hpp"
#include "slicecap/hwcheck/white_rows.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/room_light.hpp"

namespace slicecap::hwcheck {
namespace {

std::shared_ptr<test::StillScene> stillScene() {
  static const auto scene = [] {
    auto renderer = std::make_shared<sim::FrameRenderer>(
        vision::defaultSimulatedCamera(), vision::defaultTarget(),
        sim::loadMaterial("matte-paint"), sim::RigParams::realistic());
    return std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
  }();
  return scene;
}

// An empty desk: the target is not in view.
class EmptyScene final : public hal::SceneSource {
 public:
  EmptyScene() : light_(std::make_shared<hal::SceneLight>()) {
    const auto& k = vision::defaultSimulatedCamera().intrinsics;
    light_->widthPx = k.widthPx;
    light_->heightPx = k.heightPx;
    light_->ledRate.assign(std::size_t(k.widthPx) * k.heightPx * 3, 20.0f);
    light_->ambientRate.assign(std::size_t(k.widthPx) * k.heightPx * 3, 2.0f);
  }
  std::string id() const override { return "empty desk"; }
  std::shared_ptr<const hal::SceneLight> lightAt(std::int64_t) override { return light_; }

 private:
  std::shared_ptr<hal::SceneLight> light_;
};

constexpr std::int64_t kLedDelayUs = 40;  // the physical LED's light after the command

struct ModelRig {
  hal::FakeClock clock{5'000'000};
  std::shared_ptr<hal::LedTimeline> light = std::make_shared<hal::LedTimeline>();
  hal::TimelineLed led{std::make_unique<test::PlainLed>(), clock, light, kLedDelayUs};
  hal::SensorModel model;
  std::unique_ptr<hal::ModelCamera> camera;

  explicit ModelRig(hal::SensorModel m, std::shared_ptr<hal::SceneSource> scene = stillScene())
      : model(m) {
    model.realTime = false;
    model.holdSceneUntilStrobe = false;
    camera = std::make_unique<hal::ModelCamera>(std::move(scene), light, clock, model);
  }
  HardwareReport run(HardwareCheckOptions options = {}) { return runOn(*camera, options); }
  HardwareReport runOn(hal::Camera& on, HardwareCheckOptions options = {}) {
    options.captureSeconds = 0.5;  // 15 frames: enough for a period and a drop count
    BackendInfo backend{{"model camera"}, Verdict::Warn, "none: the model delivers ISP output", ""};
    return runHardwareCheck(on, {}, led, clock, vision::defaultTarget(),
                            vision::defaultSimulatedCamera(), backend, options);
  }
};

const CheckItem& item(const HardwareReport& report, const std::string& name) {
  for (const CheckItem& i : report.items)
    if (i.name == name) return i;
  throw std::runtime_error("no item " + name + " in\n" + report.text());
}

TEST(HardwareCheck, ReportsTheModelsConfiguredTimingAndCurve) {
  hal::SensorModel sensor;  // the defaults: a camera module 3 at 1280 x 720 behind the Pi's ISP
  // The noise check reads the noise the frames carry: a Pi 5's temporal denoise lowers it on a
  // still target and a colour matrix mixes the channels', so the sensor's own comes back only
  // with both off (as slicecap's tuning file for the processed path sets them, issue 44).
  sensor.isp.colourMatrix = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  sensor.isp.temporalDenoiseWeight = 0.0;
  // The LED's offset is read from the frames' timestamps around a switch: with the Pi's 20 us
  // timestamp jitter one run read 18 us for the model's 40 (issue 44; the check does not yet
  // average over switches), so the timing is checked on the frame grid.
  sensor.isp.timestampJitterUs = 0.0;
  ModelRig rig(sensor);
  const HardwareReport report = rig.run();
  std::printf("%s\n", report.text().c_str());
  const MeasuredFigures& f = report.figures;
  const double readoutUs = sensor.lineTimeUs * 720;
  ASSERT_TRUE(f.readoutUs) << report.text();
  EXPECT_NEAR(*f.readoutUs, readoutUs, 0.1 * readoutUs);
  ASSERT_TRUE(f.ledOffsetUs);
  EXPECT_NEAR(*f.ledOffsetUs, double(kLedDelayUs), 0.1 * double(kLedDelayUs) + 10.0)
      << "10 us: a quarter of a line";
  ASSERT_TRUE(f.deliveryLatencyUs);
  EXPECT_NEAR(*f.deliveryLatencyUs, sensor.deliveryLatencyUs, 0.1 * sensor.deliveryLatencyUs);
  ASSERT_TRUE(f.framePeriodUs);
  EXPECT_NEAR(*f.framePeriodUs, sensor.framePeriodUs, 0.01 * sensor.framePeriodUs);
  EXPECT_EQ(f.framesDropped, 0);
  EXPECT_EQ(f.exposureLockDelayFrames, sensor.controlDelayFrames);
  ASSERT_TRUE(report.responseCurve);
  // The curve against the model's own, over the codes the bracket covered (above the darkest,
  // where 8-bit steps are large), as ratios to the brightest: what decoding uses.
  ASSERT_TRUE(report.responseRange);
  const auto [lowCode, highCode] = *report.responseRange;
  EXPECT_LT(lowCode, 20.0);
  EXPECT_GT(highCode, 200.0);
  const double curveError = curveDistance(*report.responseCurve, sensor.tone, 20, highCode, highCode);
  std::printf("curve against the model's, codes 20..%.1f: %.2f %%\n", highCode, 100 * curveError);
  EXPECT_LT(curveError, 0.10);
  EXPECT_GT(*f.curveFromSrgb, 0.10) << "the IMX708 curve is not sRGB";
  EXPECT_EQ(item(report, "LED timing and readout").verdict, Verdict::Ok);
  EXPECT_EQ(item(report, "response curve").verdict, Verdict::Warn);  // not sRGB: says what to do
  // Noise: the ISP's red gain (1.9, the largest) scales red's noise, the noisiest channel's:
  // read noise x 1.9, shot noise as 8000 / 1.9 electrons, through the measured curve.
  ASSERT_TRUE(f.sensorReadNoise && f.sensorFullWellElectrons) << report.text();
  const double redGain = sensor.colourGains[0];
  std::printf("noise: read %.5f (model %.5f), full well %.0f (model %.0f)\n", *f.sensorReadNoise,
              sensor.readNoise * redGain, *f.sensorFullWellElectrons, sensor.fullWellElectrons / redGain);
  EXPECT_NEAR(*f.sensorReadNoise, sensor.readNoise * redGain, 0.2 * sensor.readNoise * redGain);
  EXPECT_NEAR(*f.sensorFullWellElectrons, sensor.fullWellElectrons / redGain,
              0.1 * sensor.fullWellElectrons / redGain);
  ASSERT_EQ(report.configLines.size(), 5u);
  EXPECT_EQ(report.configLines[0].first, "sensor_read_noise");
  EXPECT_EQ(report.configLines[1].first, "sensor_full_well_electrons");
  EXPECT_EQ(report.configLines[2].first, "readout_us");
  EXPECT_EQ(report.configLines[3].first, "led_guard_us");
  // The model's room light flickers at 100 Hz by default (a 50 Hz country's lamps).
  EXPECT_EQ(report.configLines[4], (std::pair<std::string, std::string>{"mains_hz", "50"}));
  EXPECT_FALSE(rig.led.isOn()) << "the LED is left off";
}

// The room light over the white references as a fraction of the LED's, as the model's scene has
// it (the ISP's colour gains weigh both alike).
double sceneRoomToLed(const test::StillScene& scene, const hal::SensorModel& sensor) {
  const WhiteRows whites =
      whiteRowsOf(vision::defaultTarget(), vision::defaultSimulatedCamera(), test::stillPose());
  const hal::SceneLight& light = scene.light();
  double room = 0.0, led = 0.0;
  for (std::size_t row = 0; row < whites.columnsByRow.size(); ++row)
    for (int col : whites.columnsByRow[row])
      for (int c = 0; c < 3; ++c) {
        const std::size_t at = (row * std::size_t(light.widthPx) + std::size_t(col)) * 3 + c;
        room += sensor.colourGains[c] * light.ambientRate[at];
        led += sensor.colourGains[c] * light.ledRate[at];
      }
  return room / led;
}

TEST(HardwareCheck, MeasuresTheRoomLightsFlickerAndItsLevelAgainstTheLed) {
  // Issue 44's room: 15 % of the LED face-on (the rig's 1 W/sr at 300 mm: 11.1 W/m^2), 100 Hz
  // flicker 30 % deep. Goal: frequency within 1 Hz, depth and ratio within 20 %.
  sim::RigParams bright = sim::RigParams::realistic();
  bright.ambientIrradiance = sim::roomIrradianceFor(bright, 0.15);
  auto renderer = std::make_shared<sim::FrameRenderer>(vision::defaultSimulatedCamera(),
                                                       vision::defaultTarget(),
                                                       sim::loadMaterial("matte-paint"), bright);
  auto scene = std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
  hal::SensorModel sensor;
  sensor.flickerHz = 100.0;
  sensor.flickerDepth = 0.3;
  ModelRig rig(sensor, scene);
  const HardwareReport report = rig.run();
  std::printf("%s\n", report.text().c_str());
  const MeasuredFigures& f = report.figures;
  ASSERT_TRUE(f.flickerHz && f.flickerDepth && f.roomToLed) << report.text();
  const double truthRatio = sceneRoomToLed(*scene, sensor);
  std::printf("flicker %.2f Hz (model 100), depth %.3f (model 0.3), room/LED %.3f (scene %.3f)\n",
              *f.flickerHz, *f.flickerDepth, *f.roomToLed, truthRatio);
  EXPECT_NEAR(*f.flickerHz, 100.0, 1.0);
  EXPECT_NEAR(*f.flickerDepth, 0.3, 0.2 * 0.3);
  EXPECT_NEAR(*f.roomToLed, truthRatio, 0.2 * truthRatio);
  const CheckItem& room = item(report, "room light");
  EXPECT_EQ(room.verdict, Verdict::Warn) << room.finding;
  EXPECT_NE(room.advice.find("mains_hz = 50"), std::string::npos) << room.advice;
}

TEST(HardwareCheck, SaysWhenTheFrameDurationHidesTheFlicker) {
  // mains_hz = 60: 33.3 ms frames are 4 periods of a 120 Hz flicker; every frame starts at the
  // same phase, so the rows cannot show it, and the subtraction does not need them to.
  hal::SensorModel sensor;
  sensor.flickerHz = 120.0;
  sensor.flickerDepth = 0.3;
  ModelRig rig(sensor);
  HardwareCheckOptions options;
  options.captureSeconds = 0.5;
  BackendInfo backend{{"model camera"}, Verdict::Warn, "none", ""};
  hal::CameraConfig config;
  config.frameDurationUs = 1e6 / 30.0;
  const HardwareReport report = runHardwareCheck(*rig.camera, config, rig.led, rig.clock,
                                                 vision::defaultTarget(),
                                                 vision::defaultSimulatedCamera(), backend, options);
  const CheckItem& room = item(report, "room light");
  EXPECT_EQ(room.verdict, Verdict::Ok) << room.finding << " / " << room.advice;
  EXPECT_NE(room.finding.find("no flicker measured"), std::string::npos) << room.finding;
}

TEST(HardwareCheck, TargetNotInViewIsAVerdictNamingTheCamera) {
  ModelRig rig(hal::SensorModel{}, std::make_shared<EmptyScene>());
  const HardwareReport report = rig.run();
  EXPECT_EQ(item(report, "frame timing").verdict, Verdict::Ok);  // still measured
  const CheckItem& target = item(report, "target");
  EXPECT_EQ(target.verdict, Verdict::Fail);
  EXPECT_NE(target.finding.find("not in view of model:empty desk"), std::string::npos) << target.finding;
  EXPECT_NE(target.advice.find("target"), std::string::npos);
  EXPECT_EQ(item(report, "response curve").verdict, Verdict::Fail);
  EXPECT_NE(item(report, "LED timing and readout").finding.find("target is not in view"), std::string::npos);
  EXPECT_TRUE(report.configLines.empty()) << "nothing measured, nothing to configure";
  EXPECT_EQ(report.overall(), Verdict::Fail);
}

// A camera whose driver fills in no timestamps (every frame at 0) nor exposure start.
class NoTimestamps final : public hal::Camera {
 public:
  explicit NoTimestamps(hal::Camera& inner) : inner_(inner) {}
  std::string id() const override { return "uvc:no-timestamps"; }
  hal::ConfigResult configure(hal::CameraConfig& config) override { return inner_.configure(config); }
  void start() override { inner_.start(); }
  void stop() override { inner_.stop(); }
  hal::CaptureResult nextFrame(std::chrono::milliseconds timeout) override {
    hal::CaptureResult result = inner_.nextFrame(timeout);
    if (result.frame) {
      result.frame->metadata.timestampUs = 0;
      result.frame->metadata.exposureStartUs.reset();
    }
    return result;
  }
  hal::ExposureLock lockExposure(const hal::ExposureSetting& wanted) override {
    return inner_.lockExposure(wanted);
  }

 private:
  hal::Camera& inner_;
};

TEST(HardwareCheck, ACameraWithoutTimestampsIsAVerdictSayingWhatToConfigure) {
  ModelRig rig(hal::SensorModel{});
  NoTimestamps camera(*rig.camera);
  const HardwareReport report = rig.runOn(camera);
  const CheckItem& timing = item(report, "frame timing");
  EXPECT_EQ(timing.verdict, Verdict::Fail);
  EXPECT_NE(timing.finding.find("uvc:no-timestamps"), std::string::npos) << timing.finding;
  EXPECT_NE(timing.advice.find("led_frames_per_state"), std::string::npos) << timing.advice;
  const CheckItem& led = item(report, "LED timing and readout");
  EXPECT_EQ(led.verdict, Verdict::Fail);
  EXPECT_NE(led.finding.find("no timestamps"), std::string::npos) << led.finding;
  EXPECT_FALSE(report.figures.readoutUs);
  // The noise needs no timestamps; nothing timed is configured.
  for (const auto& [key, value] : report.configLines)
    EXPECT_TRUE(key == "sensor_read_noise" || key == "sensor_full_well_electrons") << key;
}

// A camera that settles on another size than asked, as the libcamera backend does with a RAW
// mode binned 2 x 2 (2304 x 1296 delivered as 1152 x 648 for a 1280 x 720 request).
class SettlesOnItsOwnSize final : public hal::Camera {
 public:
  SettlesOnItsOwnSize(hal::Camera& inner, int widthPx, int heightPx)
      : inner_(inner), widthPx_(widthPx), heightPx_(heightPx) {}
  std::string id() const override { return inner_.id(); }
  hal::ConfigResult configure(hal::CameraConfig& config) override {
    const bool asked = config.widthPx == widthPx_ && config.heightPx == heightPx_;
    config.widthPx = widthPx_;
    config.heightPx = heightPx_;
    hal::ConfigResult result = inner_.configure(config);
    if (!asked && result.status == hal::ConfigResult::Status::Valid)
      result = {hal::ConfigResult::Status::Adjusted, "size set to the RAW mode's binned size"};
    return result;
  }
  void start() override { inner_.start(); }
  void stop() override { inner_.stop(); }
  hal::CaptureResult nextFrame(std::chrono::milliseconds timeout) override { return inner_.nextFrame(timeout); }
  hal::ExposureLock lockExposure(const hal::ExposureSetting& wanted) override {
    return inner_.lockExposure(wanted);
  }

 private:
  hal::Camera& inner_;
  int widthPx_, heightPx_;
};

TEST(HardwareCheck, FollowsTheSizeARawStreamDeliversAndSaysItNeedsNoCurve) {
  // The sensor seen at half the calibration's size through a RAW stream; the check is given the
  // 1280 x 720 calibration, as slicecapd's configuration gives it.
  const vision::CameraModel half = vision::defaultSimulatedCamera().scaledTo(640, 360);
  auto renderer = std::make_shared<sim::FrameRenderer>(half, vision::defaultTarget(),
                                                       sim::loadMaterial("matte-paint"),
                                                       sim::RigParams::realistic());
  auto scene = std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
  hal::SensorModel sensor;
  sensor.rawFormat = hal::bayerFormatFromLibcameraName("SRGGB10_CSI2P");
  sensor.pipeline = hal::ModelPipeline::Vc4;  // a Pi 4 grants the packed format as asked
  ModelRig rig(sensor, scene);
  SettlesOnItsOwnSize camera(*rig.camera, 640, 360);
  const HardwareReport report = rig.runOn(camera);
  std::printf("%s\n", report.text().c_str());
  EXPECT_EQ(item(report, "target").verdict, Verdict::Ok) << report.text();
  const CheckItem& raw = item(report, "RAW");
  EXPECT_EQ(raw.verdict, Verdict::Ok);
  EXPECT_NE(raw.finding.find("SRGGB10_CSI2P"), std::string::npos) << raw.finding;
  EXPECT_NE(raw.finding.find("640 x 360"), std::string::npos) << raw.finding;
  EXPECT_EQ(item(report, "response curve").verdict, Verdict::Ok) << "linear frames need no curve";
  EXPECT_FALSE(report.responseCurve);
  // RAW: no colour gains; R and B are single samples (green, two averaged, is quieter), so the
  // noisiest channel carries the sensor's own noise.
  ASSERT_TRUE(report.figures.sensorReadNoise && report.figures.sensorFullWellElectrons) << report.text();
  EXPECT_NEAR(*report.figures.sensorReadNoise, sensor.readNoise, 0.2 * sensor.readNoise);
  EXPECT_NEAR(*report.figures.sensorFullWellElectrons, sensor.fullWellElectrons, 0.1 * sensor.fullWellElectrons);
  // The rows are the delivered frame's: its 360 rows read out in 360 line times.
  ASSERT_TRUE(report.figures.readoutUs) << report.text();
  EXPECT_NEAR(*report.figures.readoutUs, sensor.lineTimeUs * 360, 0.1 * sensor.lineTimeUs * 360);
}

TEST(HardwareCheck, ACameraThatDeliversAnotherCropFailsNamingBothSizes) {
  ModelRig rig(hal::SensorModel{});
  SettlesOnItsOwnSize camera(*rig.camera, 640, 480);  // 4:3 from a 16:9 calibration
  const HardwareReport report = rig.runOn(camera);
  bool named = false;
  for (const CheckItem& i : report.items)
    if (i.name == "camera" && i.verdict == Verdict::Fail) {
      named = true;
      EXPECT_NE(i.finding.find("640 x 480"), std::string::npos) << i.finding;
      EXPECT_NE(i.finding.find("1280 x 720"), std::string::npos) << i.finding;
      EXPECT_NE(i.advice.find("calibrate"), std::string::npos) << i.advice;
    }
  EXPECT_TRUE(named) << report.text();
  EXPECT_EQ(report.overall(), Verdict::Fail);
  EXPECT_FALSE(report.figures.readoutUs) << "nothing is measured through the wrong calibration";
}

// A recording of the still target from the model camera, LED on throughout.
std::filesystem::path modelRecording(int frames) {
  hal::SensorModel sensor;
  sensor.isp.timestampJitterUs = 0.0;  // frames on the grid: the recording's period is checked
  ModelRig rig(sensor);
  rig.led.set(true);
  hal::CameraConfig config;
  config.exposureUs = 2000.0;
  rig.camera->configure(config);
  rig.camera->start();
  const auto dir = test::freshTempDir() / "still";
  io::Recording header;
  header.camera = vision::defaultSimulatedCamera();
  header.target = vision::defaultTarget();
  io::RecordingWriter writer(dir, header);
  for (int i = 0; i < frames; ++i) {
    hal::CaptureResult result = rig.camera->nextFrame(std::chrono::milliseconds(1000));
    if (!result.frame) throw std::runtime_error("the model camera gave no frame");
    const hal::FrameMetadata& m = result.frame->metadata;
    writer.append(result.frame->image, {"", m.timestampUs, true, m.exposureUs, m.gain});
  }
  return dir;
}

TEST(HardwareCheck, OnTheFileCameraSaysWhatARecordingCannotAnswer) {
  hal::FakeClock clock{1'000'000};
  hal::FileCameraOptions options;
  options.paced = true;
  hal::FileCamera camera(modelRecording(50), clock, options);
  test::PlainLed led;
  HardwareCheckOptions checkOptions;
  checkOptions.captureSeconds = 0.5;
  checkOptions.led.referenceFrames = 2;  // a short recording
  const BackendInfo backend{{"file camera"}, Verdict::Warn, "none: a recording", ""};
  const HardwareReport report =
      runHardwareCheck(camera, {}, led, clock, vision::defaultTarget(),
                       vision::defaultSimulatedCamera(), backend, checkOptions);
  std::printf("%s\n", report.text().c_str());
  // What it can say: the recorded frames' timing, and where the target is.
  EXPECT_EQ(item(report, "frame timing").verdict, Verdict::Ok);
  ASSERT_TRUE(report.figures.framePeriodUs);
  EXPECT_NEAR(*report.figures.framePeriodUs, 33333.0, 1.0);
  EXPECT_EQ(item(report, "target").verdict, Verdict::Ok);
  // What it cannot: its exposure is what was recorded, and the LED does not reach its frames.
  const CheckItem& lock = item(report, "exposure lock");
  EXPECT_EQ(lock.verdict, Verdict::Fail);
  EXPECT_NE(lock.finding.find("refused"), std::string::npos) << lock.finding;
  const CheckItem& ledItem = item(report, "LED timing and readout");
  EXPECT_EQ(ledItem.verdict, Verdict::Fail);
  EXPECT_NE(ledItem.finding.find("did not change when the LED switched"), std::string::npos)
      << ledItem.finding;
  EXPECT_NE(ledItem.advice.find("file camera"), std::string::npos) << ledItem.advice;
  EXPECT_TRUE(report.configLines.empty());
  EXPECT_FALSE(led.isOn());
}

}  // namespace
}  // namespace slicecap::hwcheck
