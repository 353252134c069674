// DecodingWatch's refusal on small frames made by the camera model's ISP stage (hal::model_isp::
// IspStage: adaptive contrast, the colour matrix, a Pi 5's temporal denoise, a YUV420 stream): a
// saturated blue window read LED-on less LED-off, as the live loop reads a sample, through the
// IMX708 colour matrix and a Rec.709 YUV420 stream (the processed-isp case of issue 44) and
// through the ISPs whose decoding holds (the fixed one, the model's defaults).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>
#include <random>
#include <string>

#include "slicecap/capture/area_reading.hpp"
#include "slicecap/daemon/decoding_watch.hpp"
#include "slicecap/hal/model_isp_stage.hpp"

namespace slicecap::daemon {
namespace {

constexpr int kWidthPx = 120, kHeightPx = 90;

// A small camera straight above the target from 300 mm (2 px per mm): the window is the frame's
// middle 80 x 60 px.
vision::CameraModel smallCamera() {
  vision::CameraModel camera;
  camera.intrinsics = {kWidthPx, kHeightPx, 600.0, 600.0, 59.5, 44.5};
  return camera;
}

vision::Pose fromAbove() {
  return vision::lookAtPose({0.0, 0.0, 300.0}, Eigen::Vector3d::Zero(), {0.0, 1.0, 0.0});
}

// Light `level` (linear, full scale 1, after the colour gains), `top` in the rows above the
// middle, with the sensor's read and shot noise, as the model's sensor hands it to the ISP.
Image sensorImage(const Rgb& level, std::mt19937& random, std::optional<Rgb> top = std::nullopt) {
  Image image{kWidthPx, kHeightPx, 3, 16, {}};
  std::normal_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < kWidthPx * kHeightPx; ++i) {
    const Rgb& here = top && i < kWidthPx * kHeightPx / 2 ? *top : level;
    for (int c = 0; c < 3; ++c) {
      const double sigma = std::sqrt(0.002 * 0.002 + here[c] / 8000.0);
      const double v = std::clamp(here[c] + sigma * unit(random), 0.0, 1.0);
      image.samples.push_back(static_cast<std::uint16_t>(std::lround(v * 65535.0)));
    }
  }
  return image;
}

struct WindowReading {
  Rgb light;    ///< per unit of exposure
  Rgb atBlack;  ///< fraction of pixels at code 0
};

hal::Frame processed(Image image, hal::model_isp::IspStage& isp) {
  isp.process(image);
  hal::Frame frame;
  frame.encoding = PixelEncoding::Srgb8;
  frame.image = std::move(image);
  frame.image.bitDepth = 8;
  frame.metadata.exposureUs = 1.0;
  frame.metadata.gain = 1.0;
  return frame;
}

WindowReading readRect(const hal::Frame& frame, const vision::RectMm& rect,
                       const capture::CodeTable& codes) {
  const capture::AreaReading area =
      capture::readArea(frame, fromAbove(), smallCamera(), {rect, 1.0}, {}, codes);
  return {area.mean, area.atBlack};
}

WindowReading readWindow(Image image, hal::model_isp::IspStage& isp, const capture::CodeTable& codes) {
  return readRect(processed(std::move(image), isp), {-20.0, -15.0, 20.0, 15.0}, codes);
}

// 8 LED blocks of 2 frames on, 2 off through one ISP (its stretch and denoise carry from frame
// to frame); each LED-on frame a sample whose window light is its reading less the LED-off
// frame's before it, as the live loop subtracts the room light.
DecodingWatch watchThrough(const hal::ModelIsp& ispSettings, const Rgb& windowLight) {
  const ToneCurve tone = ToneCurve::imx708Tuning();
  hal::model_isp::IspStage isp(ispSettings, hal::ModelPipeline::PiSp, tone,
                               {float(1.0 / 8000.0), float(0.002 * 0.002)});
  const capture::CodeTable codes(tone);
  std::mt19937 random(7);
  DecodingWatch watch;
  std::uint64_t sequence = 0;
  std::optional<Rgb> dark;
  for (int block = 0; block < 8; ++block)
    for (int frame = 0; frame < 4; ++frame, ++sequence) {
      const bool ledOn = frame < 2;
      const WindowReading reading =
          readWindow(sensorImage(ledOn ? windowLight : Rgb{}, random), isp, codes);
      if (!ledOn) {
        dark = reading.light;
        continue;
      }
      if (!dark) continue;
      capture::FrameOutcome outcome;
      outcome.kind = capture::FrameOutcome::Kind::Sample;
      outcome.measurement.windowAtBlack = reading.atBlack;
      outcome.measurement.windowLight = reading.light - *dark;
      watch.note(outcome, sequence);
    }
  return watch;
}

// satin-blue-45's window in a sweep, after the model's colour gains: red and green about 0.01 of
// full scale, blue six times that (docs/results/2026-12-06-real-sensors-goals.md); and the same
// with a white highlight (0.006) on it, which brings the matrix's green nearer black.
const Rgb kSatinBlue{0.010, 0.010, 0.060};
const Rgb kSatinBlueHighlight{0.016, 0.016, 0.066};
// A dim red, its LED light one standard deviation of the sensor's noise at black (0.002): a third
// of the window's pixels at code 0, as satin-blue's red at the 75 deg views.
const Rgb kDimRed{0.002, 0.010, 0.060};

hal::ModelIsp piIsp() {
  hal::ModelIsp isp;  // the model's defaults: adaptive contrast, temporal denoise, identity, RGB
  isp.colourMatrix = hal::kImx708ColourMatrix;
  isp.yuvStream = hal::YuvEncoding{hal::YcbcrMatrix::Rec709, hal::YuvRange::Limited};
  return isp;
}

TEST(DecodingWatchOnTheIsp, RefusesAWindowChannelTheColourMatrixTookBelowBlack) {
  for (const Rgb& light : {kSatinBlue, kSatinBlueHighlight}) {
    SCOPED_TRACE(light.g());
    const DecodingWatch watch = watchThrough(piIsp(), light);
    const control::DecodingCheckView figures = watch.view();
    ASSERT_TRUE(figures.windowUnlitSigmas);
    EXPECT_EQ(figures.windowUnlitChannel, "G");
    EXPECT_LT(*figures.windowUnlitSigmas, -DecodingWatch::kMinBelowBlackSigmas);
    const std::optional<std::string> refusal = watch.refusal();
    ASSERT_TRUE(refusal);
    EXPECT_NE(refusal->find("window's G"), std::string::npos) << *refusal;
    EXPECT_NE(refusal->find("camera_raw"), std::string::npos) << *refusal;
  }
}

TEST(DecodingWatchOnTheIsp, AcceptsTheIspsThatKeepEveryChannel) {
  hal::ModelIsp yuvIdentity = piIsp();
  yuvIdentity.colourMatrix = hal::ModelIsp{}.colourMatrix;
  for (const auto& [name, isp] : {std::pair{"fixed", hal::fixedModelIsp()},
                                  std::pair{"defaults", hal::ModelIsp{}},
                                  std::pair{"yuv420, identity", yuvIdentity}})
    for (const Rgb& light : {kSatinBlue, kSatinBlueHighlight, kDimRed}) {
      SCOPED_TRACE(std::string(name) + ", green " + std::to_string(light.g()));
      const DecodingWatch watch = watchThrough(isp, light);
      ASSERT_TRUE(watch.view().windowUnlitSigmas);
      EXPECT_GT(*watch.view().windowUnlitSigmas, 0.0);
      EXPECT_FALSE(watch.refusal());
    }
}

// The target's white references lit to 0.3 over half the frame, the window below them: 12 LED
// blocks (2 on, 2 off) through one ISP, each LED-on frame's window light over the white's (both
// less the LED-off frame's), as the frame pipeline's sample value is.
DecodingWatch watchAgainstTheWhites(const hal::ModelIsp& ispSettings, const Rgb& windowLight) {
  const ToneCurve tone = ToneCurve::imx708Tuning();
  hal::model_isp::IspStage isp(ispSettings, hal::ModelPipeline::PiSp, tone,
                               {float(1.0 / 8000.0), float(0.002 * 0.002)});
  const capture::CodeTable codes(tone);
  std::mt19937 random(11);
  DecodingWatch watch;
  std::uint64_t sequence = 0;
  std::optional<std::pair<Rgb, Rgb>> dark;  // window, white
  for (int block = 0; block < 12; ++block)
    for (int frame = 0; frame < 4; ++frame, ++sequence) {
      const bool ledOn = frame < 2;
      const hal::Frame f = processed(
          sensorImage(ledOn ? windowLight : Rgb{}, random, ledOn ? Rgb::gray(0.3) : Rgb{}), isp);
      // The image's top rows are the white; which side of the plane they show is the pose's.
      Rgb a = readRect(f, {-25.0, -20.0, 25.0, -4.0}, codes).light;
      Rgb b = readRect(f, {-25.0, 4.0, 25.0, 20.0}, codes).light;
      if (ledOn && a.mean() < b.mean()) std::swap(a, b);
      if (!ledOn) {
        dark = std::pair{a.mean() < b.mean() ? a : b, a.mean() < b.mean() ? b : a};
        continue;
      }
      if (!dark) continue;
      const Rgb windowLed = b - dark->first, whiteLed = a - dark->second;
      capture::FrameOutcome outcome;
      outcome.kind = capture::FrameOutcome::Kind::Sample;
      outcome.measurement.windowAtBlack = Rgb{};
      outcome.measurement.windowLight =
          Rgb{windowLed[0] / whiteLed[0], windowLed[1] / whiteLed[1], windowLed[2] / whiteLed[2]};
      watch.note(outcome, sequence);
    }
  return watch;
}

// rpi.contrast's stretch (the model's, at the tuning's limits) from the frame before: the first
// LED-on frame of a block carries a dark frame's, the next a lit frame's, and satin-blue's window
// channels, between the 1 % point and the lit frame's median, move against the whites. The same
// ISP without the stretch leaves noise.
TEST(DecodingWatchOnTheIsp, WarnsOfAStretchThatMovesTheWindowAgainstTheWhites) {
  hal::ModelIsp stretched = hal::fixedModelIsp();
  stretched.adaptiveContrast = true;
  const DecodingWatch on = watchAgainstTheWhites(stretched, kSatinBlue);
  const DecodingWatch off = watchAgainstTheWhites(hal::fixedModelIsp(), kSatinBlue);
  ASSERT_TRUE(on.view().windowStep && off.view().windowStep);
  EXPECT_GT(std::abs(*on.view().windowStep), DecodingWatch::kMaxWindowStep);
  EXPECT_GT(*on.view().windowStepSigmas, DecodingWatch::kMinStepSigmas);
  const std::vector<std::string> warned = on.warnings();
  EXPECT_TRUE(std::any_of(warned.begin(), warned.end(), [](const std::string& w) {
    return w.find("against the white references steps") != std::string::npos;
  })) << testing::PrintToString(warned);
  EXPECT_LT(std::abs(*off.view().windowStep), DecodingWatch::kMaxWindowStep);
  EXPECT_TRUE(off.warnings().empty()) << testing::PrintToString(off.warnings());
}

}  // namespace
}  // namespace slicecap::daemon
