// The room-light term of an LED-on frame between two LED-off frames: weighted where the camera
// was, not when (room_light_weight.hpp), and on the virtual rig a sample whose LED-off frames
// straddle a change of the window's reflection of the room (issue 44, goal a).
#include "room_light_weight.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <filesystem>
#include <optional>
#include <tuple>
#include <vector>

#include "../support/test_support.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/capture/recording_processor.hpp"
#include "slicecap/io/recording.hpp"
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

// satin-blue-45 on the steady rig's axial 75/30 sweep (32 positions, 29 mm apart), room light at
// `roomToLed` of the LED: the lamp's reflection in the satin changes from one planned position to
// the next. Noise-free frames, exposed as the daemon meters (the brightest pixels of position
// `meteredAt`'s LED-on frame at 0.35 of full scale), 40 ms apart.
struct AxialSweep {
  explicit AxialSweep(double roomToLed, std::size_t meteredAt) {
    rig.framesPerSlice = 32;
    rig.ambientIrradiance = sim::roomIrradianceFor(rig, roomToLed);
    renderer.emplace(camera, vision::defaultTarget(), material, rig);
    plans = sim::planSweep(slice, kAxialOffsetDeg, rig, camera, renderer->target());
    std::vector<float> sorted = ratesAt(*renderer, plans.at(meteredAt), true);
    std::sort(sorted.begin(), sorted.end());
    exposureUs = 0.35 / sorted[std::size_t(0.995 * double(sorted.size() - 1))] * 1e6;
  }
  // Position `at`'s frame, the `sequence`th of the sweep.
  hal::Frame frame(std::size_t at, bool ledOn, std::uint64_t sequence) const {
    return renderedFrame(*renderer, ratesAt(*renderer, plans.at(at), ledOn), ledOn, sequence,
                         std::int64_t(sequence) * 40'000, exposureUs);
  }
  // The window centre's linear light at position `at` (per unit exposure).
  Rgb windowCentre(std::size_t at, bool ledOn) const {
    const sim::FramePlan& plan = plans.at(at);
    sim::FrameScene scene{plan.exposurePoses, plan.lightMm, ledOn, 1e6, 1.0, std::nullopt, 0};
    return renderer->windowPoint(scene, {0.0, 0.0, 0.0}).expectedLinear;
  }
  // The LED-on frame at position `on` (sequence `onSequence`) between the LED-off frames at
  // `before` (sequence 0) and `after` (`afterSequence`), as the live loop and processRecording
  // give them.
  FrameOutcome process(std::size_t before, std::size_t on, std::uint64_t onSequence,
                       std::size_t after, std::uint64_t afterSequence,
                       PipelineSettings settings = {}) const {
    settings.poseAmbientFrames = true;
    settings.windowCellsPerSide = 0;
    FramePipeline pipeline(renderer->target(), camera, settings);
    pipeline.process(frame(before, false, 0), slice);
    pipeline.setFollowingAmbientFrame(frame(after, false, afterSequence));
    return pipeline.process(frame(on, true, onSequence), slice);
  }
  double sampleError(const FrameSample& sample, int channel) const {
    const Rgb truth = material->evaluate(toUnitVector(sample.light), toUnitVector(sample.view));
    return sample.value[channel] / truth[channel] - 1.0;
  }

  sim::RigParams rig = sim::RigParams::steady();
  std::shared_ptr<const models::ReflectanceModel> material = sim::loadMaterial("satin-blue-45");
  vision::CameraModel camera = vision::defaultSimulatedCamera();
  std::optional<sim::FrameRenderer> renderer;
  SliceId slice{SliceKind::Axial, {75, 30}};
  std::vector<sim::FramePlan> plans;
  double exposureUs = 0.0;
};

// Positions 9 and 10. The LED-off frame before the LED-on frame is at the position before; the
// LED-on frame and the LED-off frame after it are at the next, the LED-on frame a third of the
// way in time: weighted in time, two thirds of its room light would be the other position's
// reflection.
TEST(RoomLightWeight, ASampleBetweenTwoPositionsTakesTheRoomLightOfItsOwn) {
  const AxialSweep sweep(0.15, 10);
  // The window centre's room light at each position, against the LED's there: the
  // precondition of the case.
  const Rgb roomFirst = sweep.windowCentre(9, false), roomSecond = sweep.windowCentre(10, false);
  const Rgb ledSecond = sweep.windowCentre(10, true) - roomSecond;
  ASSERT_GT(std::abs(roomFirst[0] - roomSecond[0]), 0.3 * ledSecond[0]);
  const FrameOutcome outcome = sweep.process(9, 10, 1, 10, 3);
  ASSERT_EQ(outcome.kind, FrameOutcome::Kind::Sample) << outcome.detail;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(sweep.sampleError(*outcome.sample, c), 0.0, 0.02) << "channel " << c;
  ASSERT_TRUE(outcome.measurement.roomLightNearestMm);
  EXPECT_LT(*outcome.measurement.roomLightNearestMm, 2.0);
}

// Frames dropped on a loaded machine: the LED-off frames around the LED-on frame at position 10
// are at positions 8 and 12, one step (29 mm) away on either side, and the lamp's reflection at
// 10 is seen by neither. Interpolated it is wrong by far more than noise; the gate rejects it
// and names why.
TEST(RoomLightUnseen, AnLedOnFrameWhoseRoomLightNoLedOffFrameSawIsRejected) {
  const AxialSweep sweep(0.15, 10);
  PipelineSettings ungated;
  ungated.maxRoomLightDistanceMm = 0.0;
  const FrameOutcome kept = sweep.process(8, 10, 5, 12, 10, ungated);
  ASSERT_EQ(kept.kind, FrameOutcome::Kind::Sample) << kept.detail;
  double worst = 0.0;
  for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(sweep.sampleError(*kept.sample, c)));
  ASSERT_GT(worst, 0.05) << "the case needs a room light the interpolation gets wrong";

  // Off by default (room_light_unseen_mm = 0); 15 mm is the value a rig sets.
  PipelineSettings gated;
  gated.maxRoomLightDistanceMm = 15.0;
  EXPECT_EQ(sweep.process(8, 10, 5, 12, 10).kind, FrameOutcome::Kind::Sample);
  const FrameOutcome outcome = sweep.process(8, 10, 5, 12, 10, gated);
  EXPECT_EQ(outcome.kind, FrameOutcome::Kind::Rejected);
  EXPECT_EQ(outcome.rejectReason, RejectReason::RoomLightUnseen) << outcome.detail;
  ASSERT_TRUE(outcome.measurement.roomLightNearestMm);
  EXPECT_GT(*outcome.measurement.roomLightNearestMm, 15.0);
  EXPECT_EQ(outcome.measurement.roomLightSequenceApart, 10);
}

// The same frames in a dark room: the LED-off frames see no room light that changes, so where
// they were does not matter and the sample is kept (a dark room loses nothing to dropped frames).
TEST(RoomLightUnseen, ARoomLightThatDoesNotChangeKeepsTheSample) {
  const AxialSweep sweep(0.0, 10);
  PipelineSettings gated;
  gated.maxRoomLightDistanceMm = 15.0;
  const FrameOutcome outcome = sweep.process(8, 10, 5, 12, 10, gated);
  ASSERT_EQ(outcome.kind, FrameOutcome::Kind::Sample) << outcome.detail;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(sweep.sampleError(*outcome.sample, c), 0.0, 0.02) << "channel " << c;
}

// A sweep captured with the gate on says so in its recording (slicecapd's record_frames), and
// processing the recording offline gates its frames as the sweep did, unless told otherwise: the
// frames of the case above, as a recording of three frames.
TEST(RoomLightUnseen, ARecordingIsProcessedWithTheGateItWasCapturedWith) {
  const AxialSweep sweep(0.15, 10);
  const auto recordingWith = [&](std::optional<double> unseenMm) {
    const auto dir = test::freshTempDir() / "rec";
    io::Recording header;
    header.createdBy = "room_light_weight_test";
    header.camera = sweep.camera;
    header.target = sweep.renderer->target();
    header.encoding = PixelEncoding::Linear16;
    header.slice = io::RecordedSlice{sweep.slice};
    header.roomLightUnseenMm = unseenMm;
    io::RecordingWriter writer(dir, header);
    for (const auto& [at, ledOn, sequence] :
         {std::tuple{8, false, 0}, std::tuple{10, true, 5}, std::tuple{12, false, 10}}) {
      const hal::Frame frame = sweep.frame(std::size_t(at), ledOn, std::uint64_t(sequence));
      writer.append(frame.image, {"", frame.metadata.timestampUs, ledOn, sweep.exposureUs, 1.0});
    }
    return dir;
  };
  const auto ledOnOutcome = [](const std::filesystem::path& dir, PipelineSettings settings) {
    const RecordingResult result = processRecording(dir, settings);
    return result.outcomes.at(1);
  };
  const auto gated = recordingWith(15.0);
  EXPECT_EQ(io::readRecording(gated).roomLightUnseenMm, std::optional<double>(15.0));
  EXPECT_EQ(ledOnOutcome(gated, {}).rejectReason, RejectReason::RoomLightUnseen);
  EXPECT_EQ(processRecording(gated, PipelineSettings{}).roomLightUnseenMm, std::optional<double>(15.0))
      << "the result (and so the report and `process`'s line) says which gate the frames went through";
  PipelineSettings off;
  off.maxRoomLightDistanceMm = 0.0;
  EXPECT_EQ(ledOnOutcome(gated, off).kind, FrameOutcome::Kind::Sample);
  EXPECT_FALSE(processRecording(gated, off).roomLightUnseenMm);
  EXPECT_EQ(ledOnOutcome(recordingWith(std::nullopt), {}).kind, FrameOutcome::Kind::Sample);
}

}  // namespace
}  // namespace slicecap::capture
