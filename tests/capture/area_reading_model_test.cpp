// readArea on the camera model's processed stream (sim -> hal -> capture): satin-blue-45's dark
// window over the white reference, each less the LED-off frame's reading (as the live loop takes
// the room light off), against the scene's LED light. The ISP clips each pixel at black, so the
// LED-off frame's plain mean reads too bright and the dark channels' ratios too low (issue 44);
// readArea reads the clipped pixels as the light they are.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "../support/bracket_rig.hpp"
#include "../support/strobed_still_rig.hpp"
#include "slicecap/capture/area_reading.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {
namespace {

// Calls `at(x, y)` with each of an area's 24 x 24 sample points, rounded to the pixel whose centre
// it falls on (as readArea takes them), on the still rig.
template <typename At>
void forEachAreaPixel(const vision::RectMm& rect, At at) {
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  const vision::Pose pose = test::stillPose();
  for (int j = 0; j < 24; ++j)
    for (int i = 0; i < 24; ++i) {
      const auto px = camera.project(pose.toCamera({rect.xMinMm + (i + 0.5) * rect.widthMm() / 24,
                                                    rect.yMinMm + (j + 0.5) * rect.heightMm() / 24,
                                                    0.0}));
      at(int(std::lround(px->x())), int(std::lround(px->y())));
    }
}

// The scene's LED light over an area.
Rgb ledLight(const hal::SceneLight& light, const vision::RectMm& rect) {
  Rgb sum;
  forEachAreaPixel(rect, [&](int x, int y) {
    const std::size_t at = (std::size_t(y) * light.widthPx + std::size_t(x)) * 3;
    for (int c = 0; c < 3; ++c) sum[c] += light.ledRate[at + c];
  });
  return sum;
}

// The plain mean of an area's decoded 8-bit pixels (what readArea took before).
Rgb plainMean(const hal::Frame& frame, const vision::RectMm& rect, const CodeTable& codes) {
  Rgb sum;
  forEachAreaPixel(rect, [&](int x, int y) {
    for (int c = 0; c < 3; ++c) sum[c] += codes[frame.image.at(x, y, c)];
  });
  return sum * (1.0 / (24 * 24));
}

TEST(AreaReadingOnTheModel, ADarkWindowLessItsLedOffFrameReadsAsTheSceneIs) {
  const auto renderer = std::make_shared<sim::FrameRenderer>(
      vision::defaultSimulatedCamera(), vision::defaultTarget(), sim::loadMaterial("satin-blue-45"),
      sim::RigParams::ideal());
  const auto scene =
      std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
  hal::SensorModel model;
  model.isp = hal::fixedModelIsp();  // one curve: the clip at black is what is tested
  test::BracketRig on(scene, model);
  const hal::Frame lit = on.take({{on.meteredExposureUs(), 1.0}}).front();
  hal::FakeClock clock{1'000'000};
  hal::ModelCamera offCamera(scene, std::make_shared<hal::LedTimeline>(false), clock, on.model);
  hal::CameraConfig config;
  offCamera.configure(config);
  offCamera.start();
  ASSERT_TRUE(offCamera.lockExposure({lit.metadata.exposureUs, 1.0}).locked);
  std::optional<hal::Frame> dark;
  for (int n = 0; n < 20 && !(dark && dark->metadata.exposureLocks >= 1); ++n)
    dark = offCamera.nextFrame(std::chrono::milliseconds(1000)).frame;
  ASSERT_TRUE(dark && dark->metadata.exposureLocks >= 1);

  const vision::TargetGeometry& target = renderer->target();
  const vision::PointMm centre = target.window.centre();
  const vision::RectMm window{centre.xMm - 8, centre.yMm - 8, centre.xMm + 8, centre.yMm + 8};
  const vision::PointMm w = target.patches.front().rect.centre();  // white-left
  const vision::RectMm white{w.xMm - 3, w.yMm - 8, w.xMm + 3, w.yMm + 8};
  const CodeTable codes(model.tone);
  const auto read = [&](const hal::Frame& frame, const vision::RectMm& rect) {
    return test::stillAreaMean(frame, rect, codes) * frame.metadata.exposureUs;
  };
  const Rgb truthWindow = ledLight(scene->light(), window), truthWhite = ledLight(scene->light(), white);
  const Rgb windowOn = read(lit, window), windowOff = read(*dark, window);
  const Rgb whiteOn = read(lit, white), whiteOff = read(*dark, white);
  const Rgb plainWindowOff = plainMean(*dark, window, codes), plainWhiteOff = plainMean(*dark, white, codes);
  const Rgb plainWindowOn = plainMean(lit, window, codes), plainWhiteOn = plainMean(lit, white, codes);
  double worst = 0.0, worstPlain = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double truth = truthWindow[c] / truthWhite[c];
    const double error = (windowOn[c] - windowOff[c]) / (whiteOn[c] - whiteOff[c]) / truth - 1.0;
    const double plain = (plainWindowOn[c] - plainWindowOff[c]) /
                             (plainWhiteOn[c] - plainWhiteOff[c]) / truth - 1.0;
    std::printf("[ channel %d ] window / white less the LED-off frame: %+.2f %% (plain means %+.2f %%)\n",
                c, 100 * error, 100 * plain);
    worst = std::max(worst, std::abs(error));
    worstPlain = std::max(worstPlain, std::abs(plain));
  }
  // 8-bit codes and 24 x 24-point means of shot and read noise; the plain means' bias is larger.
  EXPECT_LT(worst, 0.015);
  EXPECT_GT(worstPlain, 2 * worst);
}

}  // namespace
}  // namespace slicecap::capture

namespace slicecap::capture {
namespace {

// The figures behind DecodingWatch's black-reading step (scripts/decoding-check-figures): the
// still rig with satin-blue-45, the LED in blocks of 3 frames on, 3 off, each LED-on frame's
// black patch over the white strip (each less the latest LED-off frame's), and the relative step
// from one LED-on frame to the next; their mean and its standard errors, with the model's
// adaptive contrast off and on (fixed ISP otherwise). Not run unless asked: it takes seconds.
TEST(DecodingCheckFigures, BlackReadingStepWithAndWithoutAdaptiveContrast) {
  if (!std::getenv("SLICECAP_DECODING_CHECK_FIGURES"))
    GTEST_SKIP() << "SLICECAP_DECODING_CHECK_FIGURES not set (scripts/decoding-check-figures sets it)";
  const test::StillSatinRig rig;
  const vision::RectMm& black = rig.black;
  const vision::RectMm& white = rig.white;
  for (const bool adaptive : {false, true}) {
    // Switches half-way between frames' readouts; each frame classed by its truth (every row
    // lit, every row dark, or mixed).
    test::StrobedStillCamera strobed(rig.scene, adaptive, 0.93, 134);
    ASSERT_TRUE(strobed.locked);
    hal::ModelCamera& camera = *strobed.camera;
    const hal::SensorModel& model = strobed.model;
    const CodeTable codes(model.tone);
    const auto read = [&](const hal::Frame& f, const vision::RectMm& r) {
      return test::stillAreaMean(f, r, codes).mean();
    };
    std::optional<double> offBlack, offWhite, lastReading;
    std::optional<std::uint64_t> lastSequence;
    std::vector<double> steps;
    int lit = 0, dark = 0, mixed = 0;
    for (int n = 0; n < 390 && steps.size() < 48; ++n) {
      const hal::CaptureResult result = camera.nextFrame(std::chrono::milliseconds(1000));
      if (!result.frame || result.frame->metadata.exposureLocks < 1) continue;
      const hal::Frame& f = *result.frame;
      const std::optional<hal::FrameTruth> truth = camera.truth(f.metadata.sequence);
      ASSERT_TRUE(truth);
      const auto [lo, hi] = std::minmax_element(truth->rowOnFraction.begin(), truth->rowOnFraction.end());
      if (*hi < 1e-3) {
        ++dark;
        offBlack = read(f, black), offWhite = read(f, white);
      } else if (*lo > 1.0 - 1e-3 && offBlack) {
        ++lit;
        const double reading = (read(f, black) - *offBlack) / (read(f, white) - *offWhite);
        if (lastSequence && f.metadata.sequence == *lastSequence + 1)
          steps.push_back(reading / *lastReading - 1.0);
        lastReading = reading, lastSequence = f.metadata.sequence;
      } else {
        ++mixed;
      }
    }
    ASSERT_GE(steps.size(), 8u) << lit << " lit, " << dark << " dark, " << mixed << " mixed";
    double sum = 0.0, sumSquares = 0.0;
    for (double s : steps) sum += s, sumSquares += s * s;
    const double n = double(steps.size()), mean = sum / n;
    const double sd = std::sqrt(std::max(0.0, (sumSquares - n * mean * mean) / (n - 1)));
    std::printf("[ decoding check ] adaptive contrast %s: %zu steps, mean %+.3f %%, %.1f standard "
                "errors, spread %.3f %% (%d lit, %d dark, %d mixed frames)\n",
                adaptive ? "on " : "off", steps.size(), 100 * mean, std::abs(mean) / (sd / std::sqrt(n)),
                100 * sd, lit, dark, mixed);
  }
}

}  // namespace
}  // namespace slicecap::capture
