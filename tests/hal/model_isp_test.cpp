// The camera model as a Pi: RAW validated as a Pi 4 or Pi 5 validates it, and the processed
// stream's ISP (adaptive contrast, colour matrix, YUV stream, a Pi 5's temporal denoise), lock
// counting as libcamera counts, timestamp jitter.
#include "slicecap/hal/model_isp.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "slicecap/hal/model_isp_stage.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/model_camera.hpp"

namespace slicecap::hal {
namespace {

const BayerFormat kImx708{BayerOrder::Rggb, 10, BayerPacking::Csi2Packed};

TEST(ValidateRawLikePi, APi5ReplacesPackedRawByItsCompressedFormatAndUnpackedBy16Bits) {
  const std::pair<int, int> mode{2304, 1296};
  EXPECT_EQ(validateRawLikePi(ModelPipeline::PiSp, kImx708, mode, "SRGGB10_CSI2P").format,
            "RGGB_PISP_COMP1");
  EXPECT_EQ(validateRawLikePi(ModelPipeline::PiSp, kImx708, mode, "SRGGB10").format, "SRGGB16");
  EXPECT_EQ(validateRawLikePi(ModelPipeline::Vc4, kImx708, mode, "SRGGB10_CSI2P").format,
            "SRGGB10_CSI2P");
  EXPECT_EQ(validateRawLikePi(ModelPipeline::Vc4, kImx708, mode, "SRGGB16").format, "SRGGB10");
  EXPECT_TRUE(validateRawLikePi(ModelPipeline::PiSp, kImx708, mode, "YUYV").refused);
}

// A flat scene of one colour, LED light only.
class FlatScene final : public SceneSource {
 public:
  FlatScene(int width, int height, std::array<float, 3> rgb) : light_(std::make_shared<SceneLight>()) {
    light_->widthPx = width;
    light_->heightPx = height;
    for (int i = 0; i < width * height; ++i)
      light_->ledRate.insert(light_->ledRate.end(), rgb.begin(), rgb.end());
    light_->ambientRate.assign(light_->ledRate.size(), 0.0f);
  }
  std::string id() const override { return "flat"; }
  std::shared_ptr<const SceneLight> lightAt(std::int64_t) override { return light_; }

 private:
  std::shared_ptr<SceneLight> light_;
};

struct Camera {
  FakeClock clock{1'000'000};
  std::shared_ptr<LedTimeline> light = std::make_shared<LedTimeline>(true);  // the LED on
  std::unique_ptr<ModelCamera> camera;
  CameraConfig config;
  ConfigResult configured;

  explicit Camera(SensorModel model, std::array<float, 3> rgb = {20.0f, 20.0f, 20.0f}) {
    model.realTime = false;
    model.holdSceneUntilStrobe = false;
    camera = std::make_unique<ModelCamera>(std::make_shared<FlatScene>(32, 24, rgb), light, clock,
                                           model);
    config.widthPx = 32;
    config.heightPx = 24;
    config.exposureUs = 10000.0;
    configured = camera->configure(config);
    camera->start();
  }
  Frame next() {
    CaptureResult result = camera->nextFrame(std::chrono::milliseconds(1000));
    EXPECT_EQ(result.status, CaptureResult::Status::Frame) << result.error;
    return std::move(*result.frame);
  }
};

TEST(ModelCameraPipeline, APi5LikeModelRunsRawInTheUnpacked16BitFormatItGrants) {
  SensorModel model;
  model.pipeline = ModelPipeline::PiSp;
  model.rawFormat = kImx708;
  Camera pi5(model);
  // Asking once for the proposed packed format leaves RGGB_PISP_COMP1, which is not decoded:
  // only the second request, the unpacked twin, gets RAW.
  EXPECT_EQ(pi5.config.rawFormat, "SRGGB16");
  EXPECT_EQ(pi5.config.encoding, PixelEncoding::Linear16);
  EXPECT_NE(pi5.configured.reason.find("RGGB_PISP_COMP1"), std::string::npos)
      << pi5.configured.reason;
  // The 16-bit words decode to the same light as a Pi 4's packed 10-bit codes.
  model.pipeline = ModelPipeline::Vc4;
  Camera pi4(model);
  EXPECT_EQ(pi4.config.rawFormat, "SRGGB10_CSI2P");
  const Frame a = pi5.next(), b = pi4.next();
  ASSERT_EQ(a.encoding, PixelEncoding::Linear16);
  double sumA = 0.0, sumB = 0.0;
  for (std::size_t i = 0; i < a.image.samples.size(); ++i) {
    sumA += linear16Value(a.image.samples[i], a.black16);
    sumB += linear16Value(b.image.samples[i], b.black16);
  }
  EXPECT_NEAR(sumA / sumB, 1.0, 0.002);
  EXPECT_NEAR(sumA / double(a.image.samples.size()), 0.2, 0.002);  // 20 /s x 10 ms
}

TEST(ModelCameraPipeline, CameraRawOnWithoutARawStreamIsRefusedSayingSo) {
  SensorModel model;
  FakeClock clock{0};
  ModelCamera camera(std::make_shared<FlatScene>(8, 8, std::array{1.0f, 1.0f, 1.0f}),
                     std::make_shared<LedTimeline>(), clock, model);
  CameraConfig config;
  config.widthPx = 8;
  config.heightPx = 8;
  config.raw = RawCapture::On;
  const ConfigResult result = camera.configure(config);
  EXPECT_EQ(result.status, ConfigResult::Status::Invalid);
  EXPECT_NE(result.reason.find("offers no RAW"), std::string::npos) << result.reason;
}

TEST(ModelIspStretch, ADarkFramePushesItsTopUpAndKeepsItsMedian) {
  std::array<std::uint32_t, 256> dark{};
  dark[10] = 1000;  // everything near 4 % of full scale
  const model_isp::Stretch stretch = model_isp::stretchFromHistogram(dark);
  // contrast.cpp: the 95 % point, far below 95 %, moves by hi_max (2000) at most.
  bool pushed = false;
  for (const auto& [in, out] : stretch)
    if (std::abs(in - (0.95 * 65536 - 2000)) < 1.0 && std::abs(out - 0.95 * 65536) < 1.0)
      pushed = true;
  EXPECT_TRUE(pushed);
}

// The same linear light, 8-bit codes after a bright frame and after a dark one: the ISP's curve
// follows the frame before, so an LED-off frame and an LED-on frame get different curves.
TEST(ModelIspStage, AdaptiveContrastGivesTheSameLightOtherCodesAfterADarkerFrame) {
  ModelIsp isp = fixedModelIsp();
  isp.adaptiveContrast = true;
  model_isp::IspStage stage(isp, ModelPipeline::Vc4, ToneCurve::imx708Tuning(), {});
  const auto frameOf = [](std::uint16_t value) {
    Image image;
    image.width = 16;
    image.height = 16;
    image.channels = 3;
    image.samples.assign(16 * 16 * 3, value);
    return image;
  };
  Image probe = frameOf(30000);
  stage.process(probe);  // the first frame: the tuning's curve alone
  Image bright = frameOf(50000);
  stage.process(bright);
  Image afterBright = frameOf(30000);
  stage.process(afterBright);
  Image dark = frameOf(2000);
  stage.process(dark);
  Image afterDark = frameOf(30000);
  stage.process(afterDark);
  EXPECT_NE(afterBright.samples[0], afterDark.samples[0]);
  isp.adaptiveContrast = false;
  model_isp::IspStage fixed(isp, ModelPipeline::Vc4, ToneCurve::imx708Tuning(), {});
  Image a = frameOf(30000), b = frameOf(2000), c = frameOf(30000);
  fixed.process(a);
  fixed.process(b);
  fixed.process(c);
  EXPECT_EQ(a.samples[0], c.samples[0]);
}

TEST(ModelIspStage, TheColourMatrixMixesASaturatedRedAndClipsItsGreen) {
  ModelIsp isp = fixedModelIsp();
  isp.colourMatrix = kImx708ColourMatrix;
  model_isp::IspStage stage(isp, ModelPipeline::Vc4, ToneCurve::linear(), {});
  Image red;
  red.width = red.height = 2;
  red.channels = 3;
  for (int i = 0; i < 4; ++i) red.samples.insert(red.samples.end(), {32768, 0, 0});
  stage.process(red);
  EXPECT_NEAR(red.samples[0], 255.0 * 0.5 * 1.52972, 1.0);  // R + 53 %
  EXPECT_EQ(red.samples[1], 0);                             // G -0.28 R, clipped at 0
  EXPECT_NEAR(red.samples[2], 255.0 * 0.5 * 0.01695, 1.0);
}

TEST(ModelIspStage, APi5BlendsAStillPixelWithThePreviousFrameAndAPi4DoesNot) {
  ModelIsp isp = fixedModelIsp();
  isp.temporalDenoiseWeight = 0.5;
  const model_isp::NoiseLevel noise{1.0f / 8000.0f, 0.002f * 0.002f};
  const auto twoFrames = [&](ModelPipeline pipeline, std::uint16_t first, std::uint16_t second) {
    model_isp::IspStage stage(isp, pipeline, ToneCurve::linear(), noise);
    Image a, b;
    a.width = b.width = a.height = b.height = 1;
    a.channels = b.channels = 3;
    a.samples.assign(3, first);
    b.samples.assign(3, second);
    stage.process(a);
    stage.process(b);
    return b.samples[0];
  };
  // Light 0.05 of full scale: its noise is sqrt(0.05 / 8000 + 0.002^2) = 0.0032 (210 codes of
  // 65535); the LED-on frame 100 codes brighter is within it and is pulled half way back.
  EXPECT_NEAR(twoFrames(ModelPipeline::PiSp, 3277, 3377), std::lround(255.0 * 3327 / 65535), 1);
  EXPECT_NEAR(twoFrames(ModelPipeline::Vc4, 3277, 3377), std::lround(255.0 * 3377 / 65535), 0);
  // A change far beyond the noise passes on a Pi 5 too.
  EXPECT_NEAR(twoFrames(ModelPipeline::PiSp, 3277, 13277), std::lround(255.0 * 13277 / 65535), 0);
}

TEST(ModelIspStage, ARec709StreamDecodesAGreyWithinACode) {
  Image grey;
  grey.width = grey.height = 4;
  grey.channels = 3;
  grey.samples.assign(4 * 4 * 3, 0);
  for (std::size_t i = 0; i < grey.samples.size(); ++i) grey.samples[i] = 40 + (i / 3) * 10;
  const Image before = grey;
  model_isp::throughYuv420(grey, {YcbcrMatrix::Rec709, YuvRange::Limited});
  ASSERT_EQ(grey.samples.size(), before.samples.size());
  for (std::size_t i = 0; i < grey.samples.size(); ++i)
    EXPECT_NEAR(grey.samples[i], before.samples[i], 1.0) << i;
}

TEST(ModelCameraMetadata, ALockCountsFromTheFrameWhoseRequestCarriedItNotFromTheSensor) {
  SensorModel model;
  model.controlDelayFrames = 3;
  Camera camera(model);
  camera.next();  // frame 0; frames 1..4 are the four requests queued
  camera.camera->lockExposure({4000.0, 1.0});
  std::optional<std::uint64_t> firstCounted, firstTaken;
  for (int i = 0; i < 10; ++i) {
    const Frame frame = camera.next();
    const std::uint64_t sequence = frame.metadata.sequence;
    if (!firstCounted && frame.metadata.exposureLocks == 1) firstCounted = sequence;
    if (!firstTaken && camera.camera->truth(sequence)->exposureUs == 4000.0) firstTaken = sequence;
  }
  ASSERT_TRUE(firstCounted && firstTaken);
  EXPECT_EQ(*firstTaken, 4u);    // the sensor: three frames after frame 1
  EXPECT_EQ(*firstCounted, 5u);  // libcamera: the request queued behind the four
}

TEST(ModelCameraMetadata, TimestampsJitterAroundTheFramePeriodAndStayInOrder) {
  SensorModel model;
  model.isp.timestampJitterUs = 20.0;
  Camera camera(model);
  double sumSquares = 0.0;
  std::int64_t previous = 0;
  const int frames = 40;
  for (int i = 0; i < frames; ++i) {
    const Frame frame = camera.next();
    const double onGrid = 1'000'000.0 + double(frame.metadata.sequence) * model.framePeriodUs;
    const double offUs = double(frame.metadata.timestampUs) - onGrid;
    EXPECT_LE(std::abs(offUs), 81.0);
    EXPECT_GT(frame.metadata.timestampUs, previous);
    EXPECT_EQ(*frame.metadata.exposureStartUs, frame.metadata.timestampUs - 10000);
    previous = frame.metadata.timestampUs;
    sumSquares += offUs * offUs;
  }
  EXPECT_GT(std::sqrt(sumSquares / frames), 5.0);
}

}  // namespace
}  // namespace slicecap::hal
