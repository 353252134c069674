// makeLiveFramePipeline: the live loop's two-sided room light, one LED block late, giving what
// processRecording's default gives offline on the same frames; and the room-light figures the
// pipeline reports for the status.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "../support/test_support.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/capture/led_gate.hpp"
#include "slicecap/capture/recording_processor.hpp"
#include "slicecap/core/tone_curve.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/simulate.hpp"

namespace slicecap::capture {
namespace {

constexpr const char* kSpecular = "ward:diffuse=0.3,0.2,0.1,specular=0.4,ax=0.15,ay=0.2,tangent=30";

std::filesystem::path simulated(const SliceId& slice, int frames) {
  const auto dir = test::freshTempDir() / folderName(slice);
  sim::SweepSetup setup;
  setup.rig = sim::RigParams::steady();  // sensor noise and the room light, a steady hand
  setup.rig.framesPerSlice = frames;
  setup.rig.ambientIrradiance = 1.5;  // 13 % of the LED face-on
  setup.materialSpec = kSpecular;
  const sim::FrameRenderer renderer(setup.camera, setup.target, sim::loadMaterial(kSpecular),
                                    setup.rig);
  sim::simulateSweep(dir, {slice, kAxialOffsetDeg}, renderer, setup);
  return dir;
}

// These sweeps have 12 frames, 30 deg of azimuth apart: no LED-off frame is where an LED-on frame
// was, and the specular material's room light changes between them, so room_light_unseen would
// take nearly every sample; the tests here are about the term itself.
PipelineSettings withoutTheUnseenGate() {
  PipelineSettings settings;
  settings.maxRoomLightDistanceMm = 0.0;
  return settings;
}

hal::Frame frameOf(const std::filesystem::path& dir, const io::Recording& recording,
                   std::size_t index) {
  const io::RecordedFrame& entry = recording.frames[index];
  hal::Frame frame{io::readPng(io::framePath(dir, entry)), recording.encoding, {}};
  frame.metadata = {index, entry.timestampUs, entry.exposureUs, entry.gain, entry.ledOn};
  return frame;
}

TEST(LiveFramePipeline, SettlesEachLedOnFrameWithTheLedOffFrameAfterItAsOfflineDoes) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulated(slice, 12);
  const io::Recording recording = io::readRecording(dir);
  PipelineSettings settings = withoutTheUnseenGate();
  settings.poseAmbientFrames = true;  // as slicecapd's, and as offline's two-sided term
  // Offline searches each frame as long as it takes; the live loop spreads a search over frames
  // (its budget moves the first poses by ~1e-3 in the samples): the same here, so that only the
  // room-light term is compared.
  settings.detector.frameBudgetPx = std::numeric_limits<double>::infinity();
  const LiveFrameProcessor live = makeLiveFramePipeline(recording.target, recording.camera, settings);
  std::map<std::int64_t, FrameOutcome> liveOutcomes;
  std::size_t held = 0;
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    const hal::Frame frame = frameOf(dir, recording, i);
    const std::vector<SettledFrame> settled = live(&frame, slice);
    if (frame.metadata.ledOn) {
      EXPECT_TRUE(settled.empty()) << "frame " << i << " waits for the LED-off frame after it";
      ++held;
      continue;
    }
    // The held LED-on frames, then this LED-off frame, in capture order.
    ASSERT_EQ(settled.size(), held + 1) << i;
    for (std::size_t k = 0; k < settled.size(); ++k)
      EXPECT_EQ(settled[k].metadata.sequence, i - held + k);
    EXPECT_EQ(settled.back().outcome.kind, FrameOutcome::Kind::Ambient);
    held = 0;
    for (const SettledFrame& s : settled) liveOutcomes[s.metadata.timestampUs] = s.outcome;
  }
  for (const SettledFrame& s : live(nullptr, slice)) liveOutcomes[s.metadata.timestampUs] = s.outcome;
  ASSERT_EQ(liveOutcomes.size(), recording.frames.size()) << "every frame settles";

  // The offline default (two-sided, each LED-off frame at its own pose) on the same frames.
  const RecordingResult offline = processRecording(dir, withoutTheUnseenGate());
  int samples = 0;
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    const FrameOutcome& want = offline.outcomes[i];
    const FrameOutcome& got = liveOutcomes.at(recording.frames[i].timestampUs);
    ASSERT_EQ(got.kind, want.kind) << "frame " << i << ": " << got.detail;
    if (!want.sample) continue;
    ++samples;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got.sample->value[c], want.sample->value[c], 1e-9 * std::abs(want.sample->value[c]))
          << "frame " << i << " channel " << c;
  }
  EXPECT_GE(samples, 5);
}

TEST(LiveFramePipeline, EachSampleSaysTheRoomLightsShareOfTheLed) {
  // 1.5 W/m^2 of room light; the LED's 1 W/sr at 300 mm and 30 deg gives the references about
  // 11.1 x cos 30 = 9.6 W/m^2: 0.156 of it.
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulated(slice, 12);
  const RecordingResult offline = processRecording(dir, withoutTheUnseenGate());
  int samples = 0;
  for (const FrameOutcome& outcome : offline.outcomes) {
    if (!outcome.sample) continue;
    ++samples;
    ASSERT_TRUE(outcome.measurement.roomToLed);
    EXPECT_NEAR(*outcome.measurement.roomToLed, 0.156, 0.2 * 0.156);
  }
  EXPECT_GE(samples, 5);
}

TEST(FramePipeline, ConsecutiveLedOffFramesSayHowMuchTheRoomLightMoved) {
  // A flicker the frame duration does not hide moves the room light from one LED-off frame to
  // the next; here the second frame's room light is 10 % brighter than the first's.
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulated(slice, 4);
  const io::Recording recording = io::readRecording(dir);
  PipelineSettings settings;
  settings.poseAmbientFrames = true;
  FramePipeline pipeline(recording.target, recording.camera, settings);
  hal::Frame first = frameOf(dir, recording, 1);
  ASSERT_FALSE(first.metadata.ledOn);
  first.metadata.sequence = 10;
  hal::Frame same = first, brighter = first, later = first;
  same.metadata.sequence = 11;
  const ToneCurve srgb = ToneCurve::srgb();
  for (std::uint16_t& code : brighter.image.samples)
    code = static_cast<std::uint16_t>(
        std::lround(255.0 * srgb.encode(std::min(1.0, 1.1 * srgb.decode(code / 255.0)))));
  brighter.metadata.sequence = 12;
  later.metadata.sequence = 14;  // a frame dropped between: not a frame period apart
  EXPECT_FALSE(pipeline.process(first, slice).measurement.roomChange);
  const FrameOutcome unchanged = pipeline.process(same, slice);
  ASSERT_TRUE(unchanged.measurement.roomChange);
  // The same pixels, located again (the tracked search's pose moves by a hair): nothing moved.
  EXPECT_LT(*unchanged.measurement.roomChange, 0.002);
  const FrameOutcome moved = pipeline.process(brighter, slice);
  ASSERT_TRUE(moved.measurement.roomChange);
  EXPECT_NEAR(*moved.measurement.roomChange, 0.1, 0.02);
  EXPECT_FALSE(pipeline.process(later, slice).measurement.roomChange);
}

TEST(LiveFramePipeline, DiffersFromTheOneSidedTermOnASpecularSweep) {
  // What the wait buys: the LED-off frame before alone (the old live loop, `--ambient previous`)
  // gives other samples where the room's reflection changes along the sweep.
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulated(slice, 12);
  PipelineSettings previous;
  previous.offlineTwoSidedAmbient = false;
  const RecordingResult oneSided = processRecording(dir, previous);
  const RecordingResult twoSided = processRecording(dir);
  double largest = 0.0;
  for (std::size_t i = 0; i < oneSided.outcomes.size(); ++i)
    if (oneSided.outcomes[i].sample && twoSided.outcomes[i].sample)
      for (int c = 0; c < 3; ++c)
        largest = std::max(largest, std::abs(oneSided.outcomes[i].sample->value[c] /
                                                 twoSided.outcomes[i].sample->value[c] -
                                             1.0));
  EXPECT_GT(largest, 1e-4);
}

TEST(LiveFramePipeline, WithoutRoomLightToWaitForEveryFrameSettlesAtOnce) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulated(slice, 4);
  const io::Recording recording = io::readRecording(dir);
  PipelineSettings settings;
  settings.requireAmbient = false;  // led_alternate = false
  const LiveFrameProcessor live = makeLiveFramePipeline(recording.target, recording.camera, settings);
  const hal::Frame first = frameOf(dir, recording, 0);
  ASSERT_TRUE(first.metadata.ledOn);
  EXPECT_EQ(live(&first, slice).size(), 1u);
}

TEST(FramePipeline, AnLedOffFrameLitWhereItShowsTheTargetIsNotRoomLight) {
  // After dropped frames the target can be far from the latest pose: the LED was off over the
  // rows that pose predicts, and on where this frame shows the references. Kept as room light it
  // carries the LED's light into the samples (a status read 303 % of the LED's with no room light).
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulated(slice, 12);
  const io::Recording recording = io::readRecording(dir);
  std::size_t on = 0;
  while (on + 1 < recording.frames.size() &&
         !(recording.frames[on].ledOn && !recording.frames[on + 1].ledOn))
    ++on;
  ASSERT_LT(on + 1, recording.frames.size());
  PipelineSettings settings;
  settings.poseAmbientFrames = true;  // as slicecapd's: each LED-off frame read at its own pose
  settings.detector.frameBudgetPx = std::numeric_limits<double>::infinity();
  FramePipeline pipeline(recording.target, recording.camera, settings);
  const hal::Frame lit = frameOf(dir, recording, on);
  const FrameOutcome first = pipeline.process(lit, slice);
  ASSERT_TRUE(first.measurement.pose) << first.detail;
  hal::Frame dark = frameOf(dir, recording, on + 1);
  const int height = dark.image.height;
  const std::size_t rowValues = std::size_t(dark.image.width) * dark.image.channels;
  // The rows the pipeline predicts from that pose (its 10 % margin): the LED came on just after
  // their exposure, while the hand moved the target an eighth of the frame down. The pixels stay
  // the LED-off frame's (the LED's step through the markers would hide them from the detector):
  // the gate reads the LED's timeline, which says the rows below the prediction were lit.
  const RowSpan predicted =
      rowsOfInterest(recording.target, recording.camera, *first.measurement.pose, height, 0.1 * height);
  ASSERT_LT(predicted.last, height - 1);
  const int shiftPx = height / 8;
  std::vector<std::uint16_t> moved(dark.image.samples.size(), 0);
  for (int y = shiftPx; y < height; ++y) {
    std::copy_n(dark.image.samples.begin() + std::ptrdiff_t((y - shiftPx) * rowValues), rowValues,
                moved.begin() + std::ptrdiff_t(y * rowValues));
  }
  dark.image.samples = std::move(moved);
  hal::LedExposure exposure;
  exposure.lineTimeUs = 10.0;
  exposure.exposureUs = 100.0;
  exposure.changes = {{std::int64_t(10 * predicted.last + 101), true}};
  dark.metadata.ledExposure = exposure;
  ASSERT_EQ(hal::LedExposure::State::Off, exposure.stateOver(predicted.first, predicted.last));

  const FrameOutcome outcome = pipeline.process(dark, slice);
  EXPECT_EQ(outcome.kind, FrameOutcome::Kind::Rejected)
      << "kept as room light, located: " << bool(outcome.measurement.pose) << " predicted "
      << predicted.first << ".." << predicted.last << " of " << height;
  EXPECT_EQ(outcome.rejectReason, RejectReason::LedTransition);
}

}  // namespace
}  // namespace slicecap::capture
