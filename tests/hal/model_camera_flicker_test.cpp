// ModelCamera's room light: it flickers per row with the rolling shutter, and a frame duration of
// whole flicker periods gives every frame the same room light row by row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/hal/hal_error.hpp"
#include "slicecap/hal/model_camera.hpp"

namespace slicecap::hal {
namespace {

// A flat scene lit by the room alone (the LED stays off).
class RoomOnlyScene final : public SceneSource {
 public:
  RoomOnlyScene(int width, int height, float ambient) : light_(std::make_shared<SceneLight>()) {
    light_->widthPx = width;
    light_->heightPx = height;
    light_->ledRate.assign(std::size_t(width) * height * 3, 0.0f);
    light_->ambientRate.assign(std::size_t(width) * height * 3, ambient);
  }
  std::string id() const override { return "room only"; }
  std::shared_ptr<const SceneLight> lightAt(std::int64_t) override { return light_; }

 private:
  std::shared_ptr<SceneLight> light_;
};

constexpr int kWidthPx = 32, kHeightPx = 720;  // a camera module 3's 720 rows, 40 us apart

SensorModel flickeringModel(double depth) {
  SensorModel model;
  model.realTime = false;
  model.readNoise = 0.0;
  model.fullWellElectrons = 0.0;
  model.colourGains = {1.0, 1.0, 1.0};
  model.tone = ToneCurve::linear();
  model.rawFormat = BayerFormat{BayerOrder::Rggb, 12, BayerPacking::Unpacked16};  // 12 bits
  model.holdSceneUntilStrobe = false;
  model.flickerHz = 100.0;
  model.flickerDepth = depth;
  model.isp = fixedModelIsp();  // timestamps on the frame grid: the test reads them
  return model;
}

struct RoomRig {
  FakeClock clock{1'000'000};
  std::shared_ptr<LedTimeline> light = std::make_shared<LedTimeline>();
  std::unique_ptr<ModelCamera> camera;
  CameraConfig config;

  RoomRig(SensorModel model, double exposureUs, std::optional<double> frameDurationUs,
          float ambientRate) {
    camera = std::make_unique<ModelCamera>(
        std::make_shared<RoomOnlyScene>(kWidthPx, kHeightPx, ambientRate), light, clock, model);
    config.widthPx = kWidthPx;
    config.heightPx = kHeightPx;
    config.exposureUs = exposureUs;
    config.frameDurationUs = frameDurationUs;
    config.raw = RawCapture::On;
    const ConfigResult result = camera->configure(config);
    EXPECT_NE(result.status, ConfigResult::Status::Invalid) << result.reason;
    camera->start();
  }
  Frame next() {
    CaptureResult result = camera->nextFrame(std::chrono::milliseconds(1000));
    EXPECT_EQ(result.status, CaptureResult::Status::Frame) << result.error;
    return std::move(*result.frame);
  }
};

// Each row's green, as a fraction of full scale above the frame's black (a RAW frame's decode keeps
// its black above 0: linear16Value takes it off).
std::vector<double> rowValues(const Frame& frame) {
  std::vector<double> rows(frame.image.height);
  for (int y = 0; y < frame.image.height; ++y) {
    double sum = 0.0;
    for (int x = 0; x < frame.image.width; ++x)
      sum += linear16Value(frame.image.at(x, y, 1), frame.black16);
    rows[y] = sum / frame.image.width;
  }
  return rows;
}

TEST(ModelCameraFlicker, EachRowIntegratesTheRoomsFlickerOverItsOwnExposure) {
  // 1 ms exposures: each row sees the 100 Hz waveform nearly as it is; 250 rows (10 ms) a period.
  RoomRig rig(flickeringModel(0.3), 1000.0, std::nullopt, 200.0f);  // mean 0.2 of full scale
  const Frame frame = rig.next();
  const std::vector<double> rows = rowValues(frame);
  const auto [low, high] = std::minmax_element(rows.begin(), rows.end());
  // The swing of a 1 ms window of a 10 ms period: depth x sinc(pi x 0.1) = 0.3 x 0.984.
  const double swing = 0.3 * std::sin(std::numbers::pi * 0.1) / (std::numbers::pi * 0.1);
  EXPECT_NEAR((*high - *low) / (*high + *low), swing, 0.01);
  EXPECT_NEAR(rows[100], rows[350], 0.002) << "one flicker period (250 rows) apart";
  EXPECT_GT(std::abs(rows[100] - rows[225]), 0.02) << "half a period apart";
  // The frame says nothing; the truth says which factor each row got.
  const std::optional<FrameTruth> truth = rig.camera->truth(frame.metadata.sequence);
  ASSERT_TRUE(truth);
  for (int row : {0, 111, 500, 719})
    EXPECT_NEAR(rows[row], 0.2 * truth->rowRoomFactor[row], 0.001) << row;
}

TEST(ModelCameraFlicker, AnExposureOfWholeFlickerPeriodsSeesNoFlicker) {
  RoomRig rig(flickeringModel(0.3), 10000.0, std::nullopt, 20.0f);
  const std::vector<double> rows = rowValues(rig.next());
  const auto [low, high] = std::minmax_element(rows.begin(), rows.end());
  EXPECT_LT(*high - *low, 0.002);
  EXPECT_NEAR(rows[360], 0.2, 0.001);
}

TEST(ModelCameraFlicker, AFrameDurationOfWholeFlickerPeriodsGivesEveryFrameTheSameRoomLightPerRow) {
  // The daemon subtracts an LED-off frame's rows from another frame's: at the model's own 33.3 ms
  // the flicker's phase moves a third of a period a frame, and each row sees another room light.
  const auto frameToFrame = [](std::optional<double> frameDurationUs) {
    RoomRig rig(flickeringModel(0.3), 2000.0, frameDurationUs, 100.0f);
    const std::vector<double> first = rowValues(rig.next());
    const Frame secondFrame = rig.next();
    const std::vector<double> second = rowValues(secondFrame);
    double largest = 0.0;
    for (std::size_t row = 0; row < first.size(); ++row)
      largest = std::max(largest, std::abs(second[row] / first[row] - 1.0));
    return std::pair{largest, secondFrame.metadata.timestampUs};
  };
  const auto [unpinned, unpinnedSecondUs] = frameToFrame(std::nullopt);
  EXPECT_GT(unpinned, 0.3) << "up to +-28 % a row at 30 % depth";
  EXPECT_EQ(unpinnedSecondUs, 1'000'000 + 33333);
  const auto [pinned, pinnedSecondUs] = frameToFrame(40000.0);  // mains_hz = 50
  EXPECT_LT(pinned, 0.002);
  EXPECT_EQ(pinnedSecondUs, 1'000'000 + 40000) << "frames 40 ms apart";
}

TEST(ModelCameraFlicker, AFrameDurationShorterThanTheReadoutIsAdjustedAndSaid) {
  FakeClock clock;
  ModelCamera camera(std::make_shared<RoomOnlyScene>(kWidthPx, kHeightPx, 1.0f),
                     std::make_shared<LedTimeline>(), clock, flickeringModel(0.1));
  CameraConfig config;
  config.widthPx = kWidthPx;
  config.heightPx = kHeightPx;
  config.frameDurationUs = 20000.0;  // 720 rows take 28.8 ms to read
  const ConfigResult result = camera.configure(config);
  EXPECT_EQ(result.status, ConfigResult::Status::Adjusted);
  EXPECT_NE(result.reason.find("frame duration set to"), std::string::npos) << result.reason;
  ASSERT_TRUE(config.frameDurationUs);
  EXPECT_NEAR(*config.frameDurationUs, 720 * 40.0 + 1000.0, 1e-6);
  EXPECT_NEAR(camera.framePeriodUs(), *config.frameDurationUs, 1e-6);
}

TEST(ModelCameraFlicker, RefusesAFlickerOutOfRangeNamingIt) {
  SensorModel model = flickeringModel(1.2);
  FakeClock clock;
  try {
    ModelCamera camera(std::make_shared<RoomOnlyScene>(4, 4, 1), std::make_shared<LedTimeline>(),
                       clock, model);
    FAIL();
  } catch (const hal::HalError& error) {
    EXPECT_NE(std::string(error.what()).find("flicker depth"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace slicecap::hal
