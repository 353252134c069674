// ModelCamera: timing as a Pi's libcamera reports it, buffer starvation, late controls, rolling
// shutter against the LED's light, and an ISP tone curve that is not sRGB.
#include "slicecap/hal/model_camera.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/hal_error.hpp"

namespace slicecap::hal {
namespace {

// A flat scene: every pixel sees the same LED and room light.
class FlatScene final : public SceneSource {
 public:
  FlatScene(int width, int height, float led, float ambient, std::int64_t endUs = 1LL << 62)
      : light_(std::make_shared<SceneLight>()), endUs_(endUs) {
    light_->widthPx = width;
    light_->heightPx = height;
    light_->ledRate.assign(std::size_t(width) * height * 3, led);
    light_->ambientRate.assign(std::size_t(width) * height * 3, ambient);
  }
  std::string id() const override { return "flat"; }
  std::shared_ptr<const SceneLight> lightAt(std::int64_t sinceStartUs) override {
    return sinceStartUs < endUs_ ? light_ : nullptr;
  }

 private:
  std::shared_ptr<SceneLight> light_;
  std::int64_t endUs_;
};

SensorModel quietModel() {
  SensorModel model;
  model.realTime = false;
  model.readNoise = 0.0;
  model.fullWellElectrons = 0.0;
  model.colourGains = {1.0, 1.0, 1.0};
  model.holdSceneUntilStrobe = false;
  // The sensor's own timing and response: an ISP that does nothing beyond the gains and the
  // curve, timestamps on the frame grid, locks counted when the sensor took them
  // (model_isp_test.cpp tests the Pi's ISP, jitter and libcamera's count).
  model.isp = fixedModelIsp();
  return model;
}

struct Rig {
  FakeClock clock{1'000'000};
  std::shared_ptr<LedTimeline> light = std::make_shared<LedTimeline>();
  std::unique_ptr<ModelCamera> camera;

  explicit Rig(SensorModel model, int bufferCount = 4, float led = 20.0f, float ambient = 2.0f,
               std::optional<double> exposureUs = 10000.0) {
    camera = std::make_unique<ModelCamera>(std::make_shared<FlatScene>(64, 48, led, ambient), light,
                                           clock, model);
    CameraConfig config;
    config.widthPx = 64;
    config.heightPx = 48;
    config.bufferCount = bufferCount;
    config.exposureUs = exposureUs;
    camera->configure(config);
    camera->start();
  }
  Frame next() {
    CaptureResult result = camera->nextFrame(std::chrono::milliseconds(1000));
    EXPECT_EQ(result.status, CaptureResult::Status::Frame) << result.error;
    return std::move(*result.frame);
  }
};

TEST(ModelCamera, DeliversFramesAfterTheirReadoutWithPiTimestamps) {
  const SensorModel model = quietModel();
  Rig rig(model);
  const Frame first = rig.next();
  EXPECT_EQ(first.metadata.sequence, 0u);
  EXPECT_EQ(first.metadata.timestampUs, 1'000'000);  // row 0's readout starts at start()
  EXPECT_EQ(*first.metadata.exposureStartUs, 1'000'000 - 10'000);
  EXPECT_FALSE(first.metadata.lineTimeUs);  // the Pi's libcamera does not say it
  // Delivered after the 48 rows are read out, plus the ISP's latency.
  EXPECT_EQ(rig.clock.nowUs(), 1'000'000 + std::int64_t(48 * model.lineTimeUs + model.deliveryLatencyUs));
  const Frame second = rig.next();
  EXPECT_EQ(second.metadata.sequence, 1u);
  EXPECT_NEAR(double(second.metadata.timestampUs - first.metadata.timestampUs),
              model.framePeriodUs, 1.0);
}

TEST(ModelCamera, DropsFramesWhenTheApplicationHoldsEveryBuffer) {
  Rig rig(quietModel(), 4);
  rig.next();
  // The application stalls for 10 frame periods: 4 buffers fill, the rest of the frames drop.
  rig.clock.advanceUs(10 * 33333);
  std::vector<std::uint64_t> sequences;
  for (int i = 0; i < 6; ++i) sequences.push_back(rig.next().metadata.sequence);
  EXPECT_EQ(sequences[0], 1u);
  EXPECT_EQ(sequences[3], 4u);
  EXPECT_GT(sequences[4], 5u) << "a sequence gap marks the dropped frames";
  EXPECT_GE(rig.camera->framesDropped(), 5u);
}

TEST(ModelCamera, AnExposureLockTakesEffectFramesLate) {
  SensorModel model = quietModel();
  model.controlDelayFrames = 3;
  Rig rig(model, 4, 20.0f, 2.0f, std::nullopt);
  const Frame first = rig.next();  // frame 0 arrives before frame 1's readout starts
  EXPECT_EQ(first.metadata.exposureUs, model.autoExposureUs);
  const ExposureLock lock = rig.camera->lockExposure({4000.0, 2.0});
  ASSERT_TRUE(lock.locked);
  std::uint64_t firstLocked = 0;
  for (int i = 0; i < 10 && !firstLocked; ++i) {
    const Frame frame = rig.next();
    if (frame.metadata.exposureLocks == 1) {
      firstLocked = frame.metadata.sequence;
      EXPECT_EQ(frame.metadata.exposureUs, 4000.0);
      EXPECT_EQ(frame.metadata.gain, 2.0);
    } else {
      EXPECT_EQ(frame.metadata.exposureUs, model.autoExposureUs) << frame.metadata.sequence;
    }
  }
  // Frame 1 was the next to start when the lock was made: three frames late is frame 4.
  EXPECT_EQ(firstLocked, 4u);
}

TEST(ModelCamera, ARollingShutterLightsOnlyTheRowsExposedAfterTheSwitch) {
  SensorModel model = quietModel();
  model.tone = ToneCurve::linear();
  Rig rig(model);
  // Frame 1's row 0 is exposed over [start + period - 10 ms, start + period); switch the LED on
  // in the middle of its rows' exposures.
  const std::int64_t frame1Row0Us = 1'000'000 + 33333 - 10000;
  rig.light->record(frame1Row0Us + std::int64_t(24 * model.lineTimeUs), true);
  rig.next();
  const Frame frame = rig.next();
  ASSERT_EQ(frame.metadata.sequence, 1u);
  const std::optional<FrameTruth> truth = rig.camera->truth(1);
  ASSERT_TRUE(truth);
  EXPECT_LT(truth->rowOnFraction[0], 1.0f);
  EXPECT_GT(truth->rowOnFraction[0], 0.9f);
  EXPECT_NEAR(truth->rowOnFraction[47], 1.0f, 1e-6);
  for (int row : {0, 20, 47}) {
    // Linear tone, unit gains: value = 0.01 s * (2 + 20 * on-fraction).
    const double expected = 0.01 * (2.0 + 20.0 * truth->rowOnFraction[row]);
    EXPECT_NEAR(frame.image.at(10, row, 1) / 255.0, expected, 0.51 / 255) << row;
  }
  EXPECT_LT(frame.image.at(10, 0, 1), frame.image.at(10, 47, 1));
}

TEST(ModelCamera, TheIspCurveAndColourGainsAreNotSrgb) {
  SensorModel model = quietModel();
  model.colourGains = {1.9, 1.0, 1.6};
  Rig rig(model);
  rig.light->record(0, true);
  const Frame frame = rig.next();
  const double linear = 0.01 * (2.0 + 20.0);  // 0.22 of full scale before the gains
  EXPECT_NEAR(frame.image.at(5, 5, 1), 255 * ToneCurve::imx708Tuning().encode(linear), 0.51);
  EXPECT_NEAR(frame.image.at(5, 5, 0), 255 * ToneCurve::imx708Tuning().encode(1.9 * linear), 0.51);
  // Read as sRGB, the green value is off by more than 10 %.
  const double asSrgb = ToneCurve::srgb().decode(frame.image.at(5, 5, 1) / 255.0);
  EXPECT_GT(std::abs(asSrgb / linear - 1.0), 0.1);
}

SensorModel rawModel() {
  SensorModel model = quietModel();
  model.rawFormat = BayerFormat{BayerOrder::Rggb, 10, BayerPacking::Csi2Packed};  // the IMX708
  model.colourGains = {1.9, 1.0, 1.6};  // the ISP's: the RAW stream never sees them
  return model;
}

TEST(ModelCamera, ItsRawStreamIsLinearPerRowThroughTheBayerDecoder) {
  const SensorModel model = rawModel();
  Rig rig(model);
  const std::int64_t frame1Row0Us = 1'000'000 + 33333 - 10000;
  rig.light->record(frame1Row0Us + std::int64_t(24 * model.lineTimeUs), true);
  rig.next();
  const Frame frame = rig.next();
  ASSERT_EQ(frame.encoding, PixelEncoding::Linear16);
  ASSERT_EQ(frame.image.bitDepth, 16);
  ASSERT_EQ(frame.image.width, 64);  // the sensor is twice the size, binned 2 x 2
  ASSERT_EQ(frame.image.height, 48);
  const std::optional<FrameTruth> truth = rig.camera->truth(1);
  ASSERT_TRUE(truth);
  for (int row : {0, 20, 47}) {
    const double expected = 0.01 * (2.0 + 20.0 * truth->rowOnFraction[row]);
    // One 10-bit code above the black level of 64 is 1/959 of full scale.
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(linear16Value(frame.image.at(10, row, c), frame.black16), expected, 0.51 / 959)
          << row << " " << c;
  }
  EXPECT_LT(frame.image.at(10, 0, 1), frame.image.at(10, 47, 1));
}

TEST(ModelCamera, ItsNoisyRawStreamAveragesToTheLightWithTheBlackLevelTakenOff) {
  SensorModel model = rawModel();
  model.readNoise = 0.002;  // about 2 codes at 10 bits
  model.fullWellElectrons = 8000.0;
  Rig rig(model, 4, 0.0f, 5.0f);  // LED dark, room light 5 x 10 ms = 0.05 of full scale
  const Frame frame = rig.next();
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0, sumSquares = 0.0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x) {
        const double v = linear16Value(frame.image.at(x, y, c), frame.black16);
        sum += v;
        sumSquares += v * v;
      }
    const double mean = sum / (64 * 48), deviation = std::sqrt(sumSquares / (64 * 48) - mean * mean);
    // A black level left in would add 64 / 959 = 0.067.
    EXPECT_NEAR(mean, 0.05, 0.0005) << c;
    // Shot and read noise, the greens' halved: sqrt(0.05 / 8000 + 0.002^2) = 0.0032.
    EXPECT_NEAR(deviation, c == 1 ? 0.0032 / std::sqrt(2.0) : 0.0032, 0.0006) << c;
  }
}

TEST(ModelCamera, RawIsTakenOnlyWhereOfferedAndAskedFor) {
  FakeClock clock;
  auto light = std::make_shared<LedTimeline>();
  const auto scene = std::make_shared<FlatScene>(64, 48, 1.0f, 1.0f);
  CameraConfig config;
  config.widthPx = 64;
  config.heightPx = 48;
  config.raw = RawCapture::On;
  ModelCamera processedOnly(scene, light, clock, quietModel());
  const ConfigResult refused = processedOnly.configure(config);
  EXPECT_EQ(refused.status, ConfigResult::Status::Invalid);
  EXPECT_NE(refused.reason.find("no RAW stream"), std::string::npos) << refused.reason;

  ModelCamera withRaw(scene, light, clock, rawModel());
  config.raw = RawCapture::Auto;
  EXPECT_EQ(withRaw.configure(config).status, ConfigResult::Status::Adjusted);
  EXPECT_EQ(config.encoding, PixelEncoding::Linear16);
  EXPECT_EQ(config.rawFormat, "SRGGB16");  // a Pi 5 (the default) grants the unpacked twin
  config.raw = RawCapture::Off;
  withRaw.configure(config);
  EXPECT_EQ(config.encoding, PixelEncoding::Srgb8);
  EXPECT_EQ(config.rawFormat, "");
  withRaw.start();
  const CaptureResult result = withRaw.nextFrame(std::chrono::milliseconds(1000));
  ASSERT_EQ(result.status, CaptureResult::Status::Frame);
  EXPECT_EQ(result.frame->encoding, PixelEncoding::Srgb8);
  EXPECT_EQ(result.frame->image.bitDepth, 8);
}

TEST(ModelCamera, TheSceneEndingEndsTheStream) {
  FakeClock clock(0);
  auto light = std::make_shared<LedTimeline>();
  ModelCamera camera(std::make_shared<FlatScene>(64, 48, 1.0f, 1.0f, 100'000), light, clock,
                     quietModel());
  CameraConfig config;
  config.widthPx = 64;
  config.heightPx = 48;
  camera.configure(config);
  camera.start();
  int frames = 0;
  for (;;) {
    const CaptureResult result = camera.nextFrame(std::chrono::milliseconds(1000));
    if (result.status != CaptureResult::Status::Frame) {
      EXPECT_EQ(result.status, CaptureResult::Status::EndOfStream);
      break;
    }
    ++frames;
  }
  EXPECT_GE(frames, 3);
  EXPECT_LE(frames, 4);
}

TEST(ModelCamera, TheSceneHoldsStillUntilTheLedFirstGoesOff) {
  // The person holds the rig while the daemon meters with the LED on; the sweep's 100 ms begin
  // once the LED strobes.
  FakeClock clock(0);
  auto light = std::make_shared<LedTimeline>();
  SensorModel model = quietModel();
  model.holdSceneUntilStrobe = true;
  ModelCamera camera(std::make_shared<FlatScene>(64, 48, 1.0f, 1.0f, 100'000), light, clock, model);
  CameraConfig config;
  config.widthPx = 64;
  config.heightPx = 48;
  camera.configure(config);
  camera.start();
  light->record(clock.nowUs(), true);
  for (int i = 0; i < 10; ++i)  // a third of a second of metering: the scene has not moved
    ASSERT_EQ(camera.nextFrame(std::chrono::milliseconds(1000)).status, CaptureResult::Status::Frame);
  light->record(clock.nowUs(), false);
  int frames = 0;
  while (camera.nextFrame(std::chrono::milliseconds(1000)).status == CaptureResult::Status::Frame)
    ASSERT_LT(++frames, 10);
  EXPECT_GE(frames, 2);
}

TEST(ModelCamera, RefusesAnInvalidModelNamingTheField) {
  SensorModel model = quietModel();
  model.lineTimeUs = -1.0;
  FakeClock clock;
  try {
    ModelCamera camera(std::make_shared<FlatScene>(4, 4, 1, 1), std::make_shared<LedTimeline>(),
                       clock, model);
    FAIL();
  } catch (const hal::HalError& error) {
    EXPECT_NE(std::string(error.what()).find("line time"), std::string::npos);
  }
}

TEST(ModelCamera, InRealTimeItsDescriptorBecomesReadableWhenAFrameIsReady) {
  SensorModel model = quietModel();
  model.realTime = true;
  SteadyClock clock;
  ModelCamera camera(std::make_shared<FlatScene>(64, 48, 1, 1), std::make_shared<LedTimeline>(),
                     clock, model);
  ASSERT_TRUE(camera.readyDescriptor());
  CameraConfig config;
  config.widthPx = 64;
  config.heightPx = 48;
  camera.configure(config);
  camera.start();
  EXPECT_EQ(camera.nextFrame(std::chrono::milliseconds(0)).status, CaptureResult::Status::Timeout);
  const CaptureResult result = camera.nextFrame(std::chrono::milliseconds(2000));
  EXPECT_EQ(result.status, CaptureResult::Status::Frame);
  camera.stop();
}

}  // namespace
}  // namespace slicecap::hal
