// The figures behind the search for a statistic that tells the camera model's adaptive contrast
// (rpi.contrast's per-frame stretch) from a fixed curve (scripts/decoding-check-figures): the
// still rig with satin-blue-45, the LED in blocks of 3 frames on, 3 off, and for each LED-on
// frame that follows another (consecutive frames, the pose and the light unchanged) the relative
// step, from the first to the second, of: the white reference's LED light per unit exposure, the
// black patch's, the window's per channel, and the black patch over the white. The stretch of an
// LED-on frame comes from the frame before: the first LED-on frame of a block carries the stretch
// of the frame read out across the LED's switch, the second an LED-on frame's. Not run unless
// asked: it takes half a minute.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../support/bracket_rig.hpp"
#include "../support/strobed_still_rig.hpp"
#include "slicecap/capture/area_reading.hpp"
#include "slicecap/hal/model_isp_stage.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {
namespace {

struct Steps {
  std::string name;
  std::vector<double> values;
};

void printSteps(const char* isp, const Steps& steps) {
  const double n = double(steps.values.size());
  if (n < 2) return;
  double sum = 0.0, sumSquares = 0.0;
  for (double s : steps.values) sum += s, sumSquares += s * s;
  const double mean = sum / n;
  const double sd = std::sqrt(std::max(0.0, (sumSquares - n * mean * mean) / (n - 1)));
  std::printf("[ stretch figures ] %s %-18s %zu steps, mean %+.3f %%, %.1f standard errors, "
              "spread %.3f %%\n",
              isp, steps.name.c_str(), steps.values.size(), 100 * mean,
              sd > 0 ? std::abs(mean) / (sd / std::sqrt(n)) : 0.0, 100 * sd);
}

TEST(AdaptiveContrastFigures, StepsFromAnLedOffFramesStretchToAnLedOnFrames) {
  if (!std::getenv("SLICECAP_DECODING_CHECK_FIGURES"))
    GTEST_SKIP() << "SLICECAP_DECODING_CHECK_FIGURES not set (scripts/decoding-check-figures sets it)";
  const test::StillSatinRig rig;
  const std::shared_ptr<test::StillScene>& scene = rig.scene;
  const vision::TargetGeometry& target = rig.target;
  const vision::RectMm& black = rig.black;
  const vision::RectMm& white = rig.white;
  const vision::PointMm c = target.window.centre();
  const vision::RectMm window{c.xMm - 8, c.yMm - 8, c.xMm + 8, c.yMm + 8};
  {
    // The stretch each frame's histogram gives (hal::model_isp::stretchFromHistogram, as the
    // model's ISP takes it: Rec.709 luminance of the linear values after the colour gains,
    // without noise), at the metered exposure with the LED on and off, and across the bracket.
    hal::SensorModel model;
    model.isp = hal::fixedModelIsp();
    const double meteredUs = test::BracketRig(scene, model).meteredExposureUs();
    const hal::SceneLight& light = scene->light();
    for (const double factor : {0.0, 1.0 / 32, 1.0 / 8, 1.0 / 2, 1.0, 2.0, 4.0}) {
      std::array<std::uint32_t, 256> histogram{};
      for (std::size_t i = 0; i + 2 < light.ledRate.size(); i += 3) {
        double rgb[3];
        for (int ch = 0; ch < 3; ++ch)
          rgb[ch] = std::min(1.0, (light.ledRate[i + ch] * factor + light.ambientRate[i + ch]) *
                                      meteredUs * 1e-6 * model.colourGains[ch]) * 65535.0;
        const auto y = std::uint32_t(54 * rgb[0] + 183 * rgb[1] + 19 * rgb[2]) >> 16;
        ++histogram[std::min<std::uint32_t>(255u, y)];
      }
      std::string points;
      for (const auto& [in, out] : hal::model_isp::stretchFromHistogram(histogram))
        points += " (" + std::to_string(int(std::lround(in))) + ", " +
                  std::to_string(int(std::lround(out))) + ")";
      std::printf("[ stretch figures ] LED light x%-6.4g of the metered exposure: stretch%s\n",
                  factor, points.c_str());
    }
  }
  for (const bool adaptive : {false, true}) {
    // Where in the frame period the LED switches (SLICECAP_STRETCH_PHASE; 0.5 by default) decides
    // what the first LED-on frame of a block follows: the frame read out across the switch, lit
    // over few of its rows at 0.5 (a dark frame's stretch, as the daemon's strobe leaves it: the
    // frame before a block is dark over the rows of interest) or over most at 0.93 (the phase of
    // DecodingCheckFigures: nearly a lit frame's stretch).
    const char* phaseText = std::getenv("SLICECAP_STRETCH_PHASE");
    const double phase = phaseText ? std::atof(phaseText) : 0.5;
    int litFrames = 0, dark = 0, mixed = 0;
    test::StrobedStillCamera strobed(scene, adaptive, phase, 200);
    ASSERT_TRUE(strobed.locked);
    hal::ModelCamera& camera = *strobed.camera;
    const hal::SensorModel& model = strobed.model;
    const CodeTable codes(model.tone);
    const auto read = [&](const hal::Frame& f, const vision::RectMm& r) {
      return test::stillAreaMean(f, r, codes);
    };
    struct Reading {
      Rgb white, black, window;
    };
    std::optional<Reading> off, last;
    std::optional<std::uint64_t> lastSequence;
    Steps whiteStep{"white", {}}, blackStep{"black", {}}, ratioStep{"black / white", {}};
    std::array<Steps, 3> windowStep{Steps{"window R", {}}, Steps{"window G", {}}, Steps{"window B", {}}};
    for (int n = 0; n < 590 && whiteStep.values.size() < 96; ++n) {
      const hal::CaptureResult result = camera.nextFrame(std::chrono::milliseconds(1000));
      if (!result.frame || result.frame->metadata.exposureLocks < 1) continue;
      const hal::Frame& f = *result.frame;
      const std::optional<hal::FrameTruth> truth = camera.truth(f.metadata.sequence);
      ASSERT_TRUE(truth);
      const auto [lo, hi] =
          std::minmax_element(truth->rowOnFraction.begin(), truth->rowOnFraction.end());
      const Reading now{read(f, white), read(f, black), read(f, window)};
      if (*hi < 1e-3) {
        ++dark;
        off = now;
        continue;
      }
      if (!(*lo > 1.0 - 1e-3)) ++mixed;
      if (!(*lo > 1.0 - 1e-3) || !off) continue;
      ++litFrames;
      const Reading lit{now.white - off->white, now.black - off->black, now.window - off->window};
      if (last && lastSequence && f.metadata.sequence == *lastSequence + 1) {
        whiteStep.values.push_back(lit.white.mean() / last->white.mean() - 1.0);
        blackStep.values.push_back(lit.black.mean() / last->black.mean() - 1.0);
        ratioStep.values.push_back((lit.black.mean() / lit.white.mean()) /
                                       (last->black.mean() / last->white.mean()) - 1.0);
        for (int ch = 0; ch < 3; ++ch)
          windowStep[ch].values.push_back(lit.window[ch] / last->window[ch] - 1.0);
      }
      last = lit, lastSequence = f.metadata.sequence;
    }
    ASSERT_GE(whiteStep.values.size(), 8u);
    const char* isp = adaptive ? "stretch on: " : "stretch off:";
    std::printf("[ stretch figures ] %s LED switching at phase %.2f: %d lit, %d dark, %d mixed frames\n",
                isp, phase, litFrames, dark, mixed);
    for (const Steps& s : {whiteStep, blackStep, ratioStep, windowStep[0], windowStep[1], windowStep[2]})
      printSteps(isp, s);
  }
}

}  // namespace
}  // namespace slicecap::capture
