// ModelCamera's noise: a flat grey frame's samples scatter with the variance the model's read and
// shot noise give, independently from sample to sample, row to row, channel to channel and frame
// to frame (the walk over the noise table), in the processed and the RAW stream.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/model_camera.hpp"

namespace slicecap::hal {
namespace {

constexpr int kWidth = 64, kHeight = 48;
constexpr double kExposureUs = 10000.0;
// Room light 30 / s over 10 ms: 0.3 of full scale, far from both clamps at this noise.
constexpr float kAmbientRate = 30.0f;
// Statistical tolerances: this many standard errors of the estimate (a few thousand samples).
constexpr double kStandardErrors = 5.0;

class GreyScene final : public SceneSource {
 public:
  GreyScene() : light_(std::make_shared<SceneLight>()) {
    light_->widthPx = kWidth;
    light_->heightPx = kHeight;
    light_->ledRate.assign(std::size_t(kWidth) * kHeight * 3, 0.0f);
    light_->ambientRate.assign(std::size_t(kWidth) * kHeight * 3, kAmbientRate);
  }
  std::string id() const override { return "grey"; }
  std::shared_ptr<const SceneLight> lightAt(std::int64_t) override { return light_; }

 private:
  std::shared_ptr<SceneLight> light_;
};

// Noise large against the 8-bit step (7 codes), a linear tone curve, unit gains and no ISP, so that a
// processed sample is the noisy linear value; `raw`: the IMX708's 10-bit RAW stream instead.
SensorModel noisyModel(bool raw) {
  SensorModel model;
  model.realTime = false;
  model.holdSceneUntilStrobe = false;
  model.tone = ToneCurve::linear();
  model.colourGains = {1.0, 1.0, 1.0};
  model.readNoise = 0.02;
  model.fullWellElectrons = 1000.0;
  // No colour matrix (it mixes the channels' noise: R's variance x 2.5 with the IMX708's, G and
  // R anti-correlated), no stretch, no temporal denoise: the sensor's noise is under test.
  model.isp = fixedModelIsp();
  if (raw) model.rawFormat = BayerFormat{BayerOrder::Rggb, 10, BayerPacking::Csi2Packed};
  return model;
}

std::vector<Frame> framesOf(const SensorModel& model, int count) {
  FakeClock clock(1'000'000);
  ModelCamera camera(std::make_shared<GreyScene>(), std::make_shared<LedTimeline>(), clock, model);
  CameraConfig config;
  config.widthPx = kWidth;
  config.heightPx = kHeight;
  config.exposureUs = kExposureUs;
  camera.configure(config);
  camera.start();
  std::vector<Frame> frames;
  while (int(frames.size()) < count) {
    CaptureResult result = camera.nextFrame(std::chrono::milliseconds(1000));
    EXPECT_EQ(result.status, CaptureResult::Status::Frame) << result.error;
    if (result.status != CaptureResult::Status::Frame) break;
    frames.push_back(std::move(*result.frame));
  }
  return frames;
}

// The standard deviation the model predicts for a delivered sample of channel `c`: shot noise
// (signal / full well) plus read noise per sensor sample, the two greens of a RAW cell averaged,
// plus the quantisation of the delivered codes (step^2 / 12).
double predictedSigma(const SensorModel& model, double signal, int c) {
  const double perSample = signal / model.fullWellElectrons + model.readNoise * model.readNoise;
  if (!model.rawFormat) return std::sqrt(perSample + 1.0 / (255.0 * 255.0 * 12.0));
  const int bits = model.rawFormat->bitDepth;
  const double codeRange = double((1 << bits) - 1) - std::ldexp(model.rawBlackLevel16, bits - 16);
  const double quantisation = 1.0 / (codeRange * codeRange * 12.0);
  const double samples = c == 1 ? 2.0 : 1.0;
  return std::sqrt((perSample + quantisation) / samples);
}

// A frame's samples less the light they saw, in units of the predicted standard deviation.
struct StandardNoise {
  std::vector<double> z;  // [y][x][c]
  double at(int x, int y, int c) const { return z[(std::size_t(y) * kWidth + x) * 3 + c]; }
};

StandardNoise standardNoise(const SensorModel& model, const Frame& frame) {
  const double signal = kAmbientRate * kExposureUs * 1e-6;
  const auto linear = [&frame](std::uint16_t sample) {
    return frame.image.bitDepth == 16 ? linear16Value(sample, frame.black16) : sample / 255.0;
  };
  StandardNoise noise;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c)
        noise.z.push_back((linear(frame.image.at(x, y, c)) - signal) /
                          predictedSigma(model, signal, c));
  return noise;
}

// Pearson's correlation of the pairs `pair` yields for each (x, y, c) it accepts.
struct Correlation {
  double value = 0.0;
  std::size_t pairs = 0;
};
Correlation correlationOf(
    const std::function<bool(int x, int y, int c, double& a, double& b)>& pair) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  std::size_t n = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c) {
        double a = 0, b = 0;
        if (!pair(x, y, c, a, b)) continue;
        sa += a;
        sb += b;
        saa += a * a;
        sbb += b * b;
        sab += a * b;
        ++n;
      }
  const double cov = sab / n - sa / n * sb / n;
  const double va = saa / n - sa / n * sa / n, vb = sbb / n - sb / n * sb / n;
  return {va > 0 && vb > 0 ? cov / std::sqrt(va * vb) : 1.0, n};
}

class ModelCameraNoise : public ::testing::TestWithParam<bool> {};

TEST_P(ModelCameraNoise, AFlatFrameHasTheReadPlusShotVarianceOfTheModel) {
  const SensorModel model = noisyModel(GetParam());
  const std::vector<Frame> frames = framesOf(model, 1);
  ASSERT_EQ(frames.size(), 1u);
  ASSERT_EQ(frames[0].encoding, GetParam() ? PixelEncoding::Linear16 : PixelEncoding::Srgb8);
  const StandardNoise noise = standardNoise(model, frames[0]);
  double sum = 0, sumSquares = 0;
  for (double z : noise.z) {
    sum += z;
    sumSquares += z * z;
  }
  const double n = double(noise.z.size());
  // Standard normal values: mean 0 (standard error 1 / sqrt(n)), variance 1 (sqrt(2 / n)).
  EXPECT_NEAR(sum / n, 0.0, kStandardErrors / std::sqrt(n)) << "the noise has a bias";
  EXPECT_NEAR(sumSquares / n, 1.0, kStandardErrors * std::sqrt(2.0 / n))
      << "variance over the model's prediction";
}

TEST_P(ModelCameraNoise, SamplesAreUncorrelatedAlongARowBetweenRowsAndBetweenChannels) {
  const SensorModel model = noisyModel(GetParam());
  const std::vector<Frame> frames = framesOf(model, 1);
  ASSERT_EQ(frames.size(), 1u);
  const StandardNoise noise = standardNoise(model, frames[0]);
  struct Offset {
    const char* what;
    int dx, dy, dc;
  };
  for (const Offset& o :
       {Offset{"next pixel in the row", 1, 0, 0}, Offset{"pixel two on in the row", 2, 0, 0},
        Offset{"pixel in the next row", 0, 1, 0}, Offset{"pixel two rows down", 0, 2, 0},
        Offset{"next channel of the pixel", 0, 0, 1}}) {
    const Correlation r = correlationOf([&](int x, int y, int c, double& a, double& b) {
      if (x + o.dx >= kWidth || y + o.dy >= kHeight || c + o.dc >= 3) return false;
      a = noise.at(x, y, c);
      b = noise.at(x + o.dx, y + o.dy, c + o.dc);
      return true;
    });
    // Independent samples: the correlation's standard error is 1 / sqrt(pairs).
    EXPECT_NEAR(r.value, 0.0, kStandardErrors / std::sqrt(double(r.pairs))) << o.what;
  }
}

TEST_P(ModelCameraNoise, TwoFramesNoiseIsIndependent) {
  const SensorModel model = noisyModel(GetParam());
  const std::vector<Frame> frames = framesOf(model, 3);
  ASSERT_EQ(frames.size(), 3u);
  for (std::size_t k = 1; k < frames.size(); ++k) {
    const StandardNoise first = standardNoise(model, frames[k - 1]);
    const StandardNoise second = standardNoise(model, frames[k]);
    const Correlation r = correlationOf([&](int x, int y, int c, double& a, double& b) {
      a = first.at(x, y, c);
      b = second.at(x, y, c);
      return true;
    });
    EXPECT_NEAR(r.value, 0.0, kStandardErrors / std::sqrt(double(r.pairs)))
        << "frames " << k - 1 << " and " << k << " share their noise";
  }
}

INSTANTIATE_TEST_SUITE_P(Streams, ModelCameraNoise, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& stream) {
                           return stream.param ? std::string("Raw") : std::string("Processed");
                         });

}  // namespace
}  // namespace slicecap::hal
