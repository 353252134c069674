// The sweep's decoding when the measured curve is refused for its residual (issue 44): the camera
// model's bracket through a curve stretched per frame (tests/support/adaptive_contrast.hpp) falls
// back to sRGB, with the figure in the note and what to change in the warning.
#include <gtest/gtest.h>

#include "../support/adaptive_contrast.hpp"
#include "../support/bracket_rig.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"
#include "slicecap/sim/material.hpp"

namespace slicecap::daemon {
namespace {

TEST(SweepDecoding, ACurveStretchedPerFrameIsRefusedAndTheFallbackSaysTheFigure) {
  const auto renderer = std::make_shared<const sim::FrameRenderer>(
      vision::defaultSimulatedCamera(), vision::defaultTarget(), sim::loadMaterial("matte-paint"),
      sim::RigParams::ideal());
  auto scene = std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
  const hal::SensorModel fixed;
  const double meteredUs = test::BracketRig(scene, fixed).meteredExposureUs();
  std::vector<hal::Frame> bracket;
  // The IPA's stretch at 8 x its limits (docs/results/2026-12-06-response-gate.md: RMS 5.35 %).
  for (const hal::ExposureSetting& setting :
       capture::BracketPlan{}.settings({meteredUs, 1.0})) {
    hal::SensorModel model = fixed;
    const double scale = setting.exposureUs * 1e-6 * setting.gain.value_or(1.0);
    model.tone = test::stretchedCurve(fixed.tone, test::histogramAt(scene->light(), fixed, scale), 8.0);
    test::BracketRig rig(scene, model);
    bracket.push_back(rig.take({setting}).front());
  }
  const SweepDecoding d =
      decodingFromBracket(std::move(bracket), "", {renderer->target(), renderer->camera()}, "model:rig");
  EXPECT_EQ(d.decoding.kind, io::RecordedDecoding::Kind::Srgb);
  EXPECT_FALSE(d.decoding.curve);
  EXPECT_NE(d.note.find("the measured curve was refused, RMS residual"), std::string::npos) << d.note;
  EXPECT_NE(d.warning.find("model:rig"), std::string::npos) << d.warning;
  EXPECT_NE(d.warning.find("camera_raw"), std::string::npos) << d.warning;
  EXPECT_NE(d.warning.find("tuning_file"), std::string::npos) << d.warning;
  EXPECT_EQ(d.warning.find("Keep the whole target in view"), std::string::npos)
      << "a refused curve is not a bracket out of view: " << d.warning;
  EXPECT_EQ(toJson(d, "model:rig")["decoding"], "srgb");
}

}  // namespace
}  // namespace slicecap::daemon
