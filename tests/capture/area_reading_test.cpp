// Area readings: every pixel inside the projected area (less the inset) is averaged, and the
// variance the noise model gives the mean is the variance the mean shows over noisy frames.
#include "slicecap/capture/area_reading.hpp"
#include "slicecap/hal/bayer_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace slicecap::capture {
namespace {

// A small camera looking straight down on the target from 300 mm: 2 px per mm at the plane.
vision::CameraModel smallCamera() {
  vision::CameraModel camera;
  camera.intrinsics = {120, 90, 600.0, 600.0, 59.5, 44.5};
  return camera;
}

vision::Pose fromAbove() {
  return vision::lookAtPose({0.0, 0.0, 300.0}, Eigen::Vector3d::Zero(), {0.0, 1.0, 0.0});
}

// A gray frame at linear `level` plus Gaussian noise of `sigma` (full scale), in `encoding`.
hal::Frame flatFrame(double level, double sigma, PixelEncoding encoding, std::mt19937& rng) {
  hal::Frame frame;
  frame.encoding = encoding;
  const bool srgb = encoding == PixelEncoding::Srgb8;
  frame.image = {120, 90, 1, srgb ? 8 : 16, {}};
  std::normal_distribution<double> noise(0.0, sigma);
  for (int i = 0; i < 120 * 90; ++i) {
    const double v = std::clamp(level + (sigma > 0 ? noise(rng) : 0.0), 0.0, 1.0);
    const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
    frame.image.samples.push_back(
        static_cast<std::uint16_t>(std::lround(srgb ? s * 255.0 : v * 65535.0)));
  }
  frame.metadata.exposureUs = 1.0;
  return frame;
}

TEST(AreaReading, AveragesThePixelsInsideTheProjectedAreaLessTheInset) {
  std::mt19937 rng(1);
  const hal::Frame frame = flatFrame(0.5, 0.0, PixelEncoding::Linear16, rng);
  const vision::RectMm rect{-10.0, -5.0, 10.0, 5.0};  // 40 x 20 px
  for (const double inset : {0.0, 3.0}) {
    SCOPED_TRACE(inset);
    const AreaReading r = readArea(frame, fromAbove(), smallCamera(), {rect, inset}, {});
    ASSERT_TRUE(r.inside);
    const double w = 40.0 - 2 * inset, h = 20.0 - 2 * inset;
    EXPECT_GE(r.pixels, (w - 1) * (h - 1));
    EXPECT_LE(r.pixels, (w + 1) * (h + 1));
    EXPECT_NEAR(r.mean[0], 0.5, 1e-4);
  }
  // Partly out of the image: not read.
  EXPECT_FALSE(
      readArea(frame, fromAbove(), smallCamera(), {{50.0, 0.0, 70.0, 10.0}, 0.0}, {}).inside);
}

TEST(AreaReading, ARawFramesBlackIsTakenOffAndItsNoiseBelowBlackCounts) {
  // A decoded RAW frame stores black at hal::kDecodedBlack16: a dark area's pixels scatter
  // either side of it, and the area's mean is the light, not the light plus the clipped half.
  std::mt19937 rng(3);
  const double level = 0.0003, sigma = 0.0026;  // 0.3 and 2.5 codes of a 10-bit sensor
  std::normal_distribution<double> noise(level, sigma);
  hal::Frame frame;
  frame.encoding = PixelEncoding::Linear16;
  frame.black16 = hal::kDecodedBlack16;
  frame.image = {120, 90, 1, 16, {}};
  for (int i = 0; i < 120 * 90; ++i)
    frame.image.samples.push_back(static_cast<std::uint16_t>(
        std::lround(hal::kDecodedBlack16 + noise(rng) * (65535.0 - hal::kDecodedBlack16))));
  frame.metadata.exposureUs = 1.0;
  const AreaReading r =
      readArea(frame, fromAbove(), smallCamera(), {{-20.0, -15.0, 20.0, 15.0}, 0.0}, {});
  ASSERT_TRUE(r.inside);
  EXPECT_NEAR(r.mean[0], level, 3.0 * sigma / std::sqrt(double(r.pixels)));
  // The same frame read through LinearView: negative below black, not 0.
  const LinearView view(frame);
  bool clipped = false;
  int below = 0;
  for (int x = 0; x < 120; ++x) below += view.linear(x, 45, 0, 0.98, &clipped) < 0.0;
  EXPECT_GT(below, 30);
  EXPECT_FALSE(clipped);
}

TEST(AreaReading, TheVarianceOfTheMeanIsTheOneNoisyFramesShow) {
  // Dark (read noise and quantisation) and bright (shot noise), in 8-bit sRGB.
  const SensorNoise model{0.002, 8000.0};
  const vision::RectMm rect{-5.0, -5.0, 5.0, 5.0};
  for (const double level : {0.005, 0.4}) {
    SCOPED_TRACE(level);
    std::mt19937 rng(7);
    const double sigma = std::sqrt(model.pixelVariance(level, 1.0));
    std::vector<double> means;
    double predicted = 0.0;
    constexpr int kFrames = 200;
    for (int k = 0; k < kFrames; ++k) {
      const hal::Frame frame = flatFrame(level, sigma, PixelEncoding::Srgb8, rng);
      const AreaReading r = readArea(frame, fromAbove(), smallCamera(), {rect, 0.0}, model);
      means.push_back(r.mean[0]);
      predicted += r.variance[0] / kFrames;
    }
    double mean = 0.0, spread = 0.0;
    for (double m : means) mean += m / kFrames;
    for (double m : means) spread += (m - mean) * (m - mean) / (kFrames - 1);
    EXPECT_NEAR(mean, level, 4 * std::sqrt(predicted / kFrames));
    // The sample variance of 200 means is within +-30 % of the truth at ~3 sigma.
    EXPECT_NEAR(spread / predicted, 1.0, 0.3);
  }
}

TEST(AreaReading, ANoiseFreeEightBitFrameKeepsItsQuantisationInTheVariance) {
  // Nothing dithers the codes: the mean is off by up to half a step, whatever the pixel count.
  std::mt19937 rng(3);
  for (const double level : {0.0041, 0.0137, 0.2213}) {
    SCOPED_TRACE(level);
    const hal::Frame frame = flatFrame(level, 0.0, PixelEncoding::Srgb8, rng);
    const AreaReading r =
        readArea(frame, fromAbove(), smallCamera(), {{-5.0, -5.0, 5.0, 5.0}, 0.0}, {0.0, 0.0});
    EXPECT_LE(std::abs(r.mean[0] - level), 2.0 * std::sqrt(r.variance[0]));
    EXPECT_GE(std::sqrt(r.variance[0]),
              quantisationStep(PixelEncoding::Srgb8, level) / std::acos(-1.0) * 0.9);
  }
}

double srgbDecoded(std::uint16_t code) {
  const double s = code / 255.0;
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

TEST(AreaReading, AnEightBitAreaClippedAtBlackReadsItsLightNotItsClippedPixels) {
  // A processed frame cannot go below black: a dark area's noisy pixels arrive clipped at code 0,
  // and their plain mean reads about 0.4 sigma too bright where the light is at black (an LED-off
  // frame, subtracted from every sample; issue 44). The area's mean is the light's.
  const double sigma = 0.004;
  const vision::RectMm rect{-20.0, -15.0, 20.0, 15.0};  // 80 x 60 px
  for (const double level : {0.0, 0.002, 0.006}) {
    SCOPED_TRACE(level);
    std::mt19937 rng(11);
    const hal::Frame frame = flatFrame(level, sigma, PixelEncoding::Srgb8, rng);
    const AreaReading r = readArea(frame, fromAbove(), smallCamera(), {rect, 0.0}, {});
    ASSERT_TRUE(r.inside);
    double plain = 0.0;
    for (std::uint16_t code : frame.image.samples) plain += srgbDecoded(code);
    plain /= double(frame.image.samples.size());
    const double standardError = sigma / std::sqrt(double(r.pixels));
    EXPECT_NEAR(r.mean[0], level, 4.0 * standardError) << "plain mean " << plain;
    EXPECT_GT(r.atBlack[0], 0.0);
    if (level == 0.0) {
      EXPECT_GT(plain - level, 20.0 * standardError);  // what was read before
    }
  }
}

TEST(AreaReading, AnEightBitAreaOfDarkAndBrightPartsKeepsItsPlainMean) {
  // Half the area at black, half lit: not one clipped Gaussian, so its plain mean stands.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.004);
  hal::Frame frame;
  frame.encoding = PixelEncoding::Srgb8;
  frame.image = {120, 90, 1, 8, {}};
  for (int i = 0; i < 120 * 90; ++i) {
    const double v = std::clamp((i % 120 < 60 ? 0.0 : 0.3) + noise(rng), 0.0, 1.0);
    const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
    frame.image.samples.push_back(static_cast<std::uint16_t>(std::lround(s * 255.0)));
  }
  frame.metadata.exposureUs = 1.0;
  const AreaReading r =
      readArea(frame, fromAbove(), smallCamera(), {{-20.0, -15.0, 20.0, 15.0}, 0.0}, {});
  ASSERT_TRUE(r.inside);
  double plain = 0.0;
  int n = 0;
  for (int y = 0; y < 90; ++y)
    for (int x = 20; x < 100; ++x) plain += srgbDecoded(frame.image.at(x, y, 0)), ++n;
  EXPECT_NEAR(r.mean[0], plain / n, 0.01 * plain / n);
}

}  // namespace
}  // namespace slicecap::capture
