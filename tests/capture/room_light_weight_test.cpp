// The room-light term of an LED-on frame between two LED-off frames: weighted where the camera
// was, not when (room_light_weight.hpp), and on the virtual rig a sample whose LED-off frames
// straddle a change of the window's reflection of the room (issue 44, goal a).
#include "room_light_weight.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig.hpp"
#include "slicecap/sim/room_light.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {
namespace {

vision::Pose cameraAt(double xMm) {
  return vision::lookAtPose({xMm, 0.0, 300.0}, {0, 0, 0}, {0, 1, 0});
}

TEST(RoomLightWeight, FollowsTheCameraCentreNotTheTime) {
  const TimedPlace before{0, cameraAt(0.0)}, after{120'000, cameraAt(30.0)};
  // Taken a third of the way in time, where the LED-off frame after it was.
  EXPECT_NEAR(roomLightWeight(before, after, {40'000, cameraAt(30.0)}), 1.0, 1e-9);
  EXPECT_NEAR(roomLightWeight(before, after, {80'000, cameraAt(0.0)}), 0.0, 1e-9);
  EXPECT_NEAR(roomLightWeight(before, after, {40'000, cameraAt(7.5)}), 0.25, 1e-6);
  // Beyond either end: the nearer frame alone.
  EXPECT_NEAR(roomLightWeight(before, after, {40'000, cameraAt(45.0)}), 1.0, 1e-9);
}

TEST(RoomLightWeight, InTimeWithoutPlacesOrWhenTheCameraStoodStill) {
  const TimedPlace before{0, cameraAt(0.0)}, after{120'000, cameraAt(30.0)};
  EXPECT_NEAR(roomLightWeight(before, after, {40'000, std::nullopt}), 1.0 / 3, 1e-9);
  EXPECT_NEAR(roomLightWeight({0, std::nullopt}, after, {40'000, cameraAt(30.0)}), 1.0 / 3, 1e-9);
  // Centres 1 mm apart are one place: the pose's noise must not pick the weight.
  EXPECT_NEAR(roomLightWeight(before, {120'000, cameraAt(1.0)}, {90'000, cameraAt(1.0)}), 0.75,
              1e-9);
  EXPECT_NEAR(roomLightWeight({5, std::nullopt}, {5, std::nullopt}, {5, std::nullopt}), 0.5, 1e-9);
}

// The virtual rig's linear light at `plan`'s pose, LED on or off: full scale per second.
std::vector<float> ratesAt(const sim::FrameRenderer& renderer, const sim::FramePlan& plan,
                           bool ledOn) {
  return renderer.renderLinear(
      {plan.exposurePoses, plan.lightMm, ledOn, 1e6, 1.0, std::nullopt, 0});
}

// A noise-free linear frame of those rates.
hal::Frame renderedFrame(const sim::FrameRenderer& renderer, const std::vector<float>& rate,
                         bool ledOn, std::uint64_t sequence, std::int64_t timeUs,
                         double exposureUs) {
  hal::Frame frame;
  frame.encoding = PixelEncoding::Linear16;
  frame.image.width = renderer.camera().intrinsics.widthPx;
  frame.image.height = renderer.camera().intrinsics.heightPx;
  frame.image.channels = 3;
  frame.image.bitDepth = 16;
  frame.image.samples.resize(rate.size());
  for (std::size_t i = 0; i < rate.size(); ++i)
    frame.image.samples[i] = static_cast<std::uint16_t>(
        std::clamp(double(rate[i]) * exposureUs * 1e-6, 0.0, 1.0) * 65535.0 + 0.5);
  frame.metadata = {sequence, timeUs, exposureUs, 1.0, ledOn};
  return frame;
}

// satin-blue-45 on the steady rig's axial 75/30 sweep, room light at 15 % of the LED (the lamp's
// reflection in the satin changes from one planned position to the next). The LED-off frame
// before the LED-on frame is at the position before; the LED-on frame and the LED-off frame
// after it are at the next, the LED-on frame a third of the way in time: weighted in time, two
// thirds of its room light would be the other position's reflection.
TEST(RoomLightWeight, ASampleBetweenTwoPositionsTakesTheRoomLightOfItsOwn) {
  sim::RigParams rig = sim::RigParams::steady();
  rig.framesPerSlice = 32;
  rig.ambientIrradiance = sim::roomIrradianceFor(rig, 0.15);
  const auto material = sim::loadMaterial("satin-blue-45");
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  const sim::FrameRenderer renderer(camera, vision::defaultTarget(), material, rig);
  const SliceId slice{SliceKind::Axial, {75, 30}};
  const std::vector<sim::FramePlan> plans =
      sim::planSweep(slice, kAxialOffsetDeg, rig, camera, renderer.target());
  const sim::FramePlan &first = plans.at(9), &second = plans.at(10);
  // The window centre's room light at each position, against the LED's there (per unit
  // exposure): the precondition of the case.
  const auto windowCentre = [&](const sim::FramePlan& plan, bool ledOn) {
    sim::FrameScene scene{plan.exposurePoses, plan.lightMm, ledOn, 1e6, 1.0, std::nullopt, 0};
    return renderer.windowPoint(scene, {0.0, 0.0, 0.0}).expectedLinear;
  };
  const Rgb roomFirst = windowCentre(first, false), roomSecond = windowCentre(second, false);
  const Rgb ledSecond = windowCentre(second, true) - roomSecond;
  ASSERT_GT(std::abs(roomFirst[0] - roomSecond[0]), 0.3 * ledSecond[0]);

  // The brightest pixels at 0.35 of full scale, as the daemon meters.
  const std::vector<float> lit = ratesAt(renderer, second, true);
  std::vector<float> sorted = lit;
  std::sort(sorted.begin(), sorted.end());
  const double exposureUs = 0.35 / sorted[std::size_t(0.995 * double(sorted.size() - 1))] * 1e6;
  const double periodUs = 40'000;
  PipelineSettings settings;
  settings.poseAmbientFrames = true;
  settings.windowCellsPerSide = 0;
  FramePipeline pipeline(renderer.target(), camera, settings);
  pipeline.process(
      renderedFrame(renderer, ratesAt(renderer, first, false), false, 0, 0, exposureUs), slice);
  const hal::Frame on = renderedFrame(renderer, lit, true, 1, std::int64_t(periodUs), exposureUs);
  pipeline.setFollowingAmbientFrame(renderedFrame(renderer, ratesAt(renderer, second, false),
                                                  false, 3, std::int64_t(3 * periodUs),
                                                  exposureUs));
  const FrameOutcome outcome = pipeline.process(on, slice);
  ASSERT_EQ(outcome.kind, FrameOutcome::Kind::Sample) << outcome.detail;
  const FrameSample& sample = *outcome.sample;
  const Rgb truth = material->evaluate(toUnitVector(sample.light), toUnitVector(sample.view));
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(sample.value[c] / truth[c], 1.0, 0.02) << "channel " << c;
}

}  // namespace
}  // namespace slicecap::capture
