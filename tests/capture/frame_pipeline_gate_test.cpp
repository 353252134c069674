// End-to-end: the white-reference gate on the virtual rig's realistic 8-bit sweeps, processed as
// recordings (sim -> capture): dark references of a frame exposed for a highlight are not taken
// for an occluder; the light arm over the references still is.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numbers>
#include <string>

#include "../support/test_support.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/capture/recording_processor.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/simulate.hpp"

namespace slicecap::capture {
namespace {

// The brushed steel: exposed for its highlight, the white references sit near 0.5 % of
// full scale at 75/75.
constexpr const char* kSteel = "ggx:diffuse=0.02,f0=0.56,ax=0.08,ay=0.3,tangent=90";
const SliceId kDarkSlice{SliceKind::Diagonal, {75, 75}};

// The realistic rig (8-bit sRGB, shot and read noise, jitter, room light, exposure changes)
// with nothing that should cost a frame but what `occlusion` asks for.
sim::RigParams realisticUnblurred(double occlusion) {
  sim::RigParams rig = sim::RigParams::realistic();
  rig.motionBlurFraction = 0.0;
  rig.markersOutOfViewFraction = 0.0;
  rig.occlusionFraction = occlusion;
  return rig;
}

std::filesystem::path simulate(const std::string& material, const SliceId& slice,
                               sim::RigParams rig, int frames) {
  const auto dir = test::freshTempDir() / folderName(slice);
  sim::SweepSetup setup;
  rig.framesPerSlice = frames;
  setup.rig = rig;
  setup.materialSpec = material;
  const sim::FrameRenderer renderer(setup.camera, setup.target, sim::loadMaterial(material),
                                    setup.rig);
  sim::simulateSweep(dir, {slice, kAxialOffsetDeg}, renderer, setup);
  return dir;
}

hal::Frame frameAt(const std::filesystem::path& dir, const io::Recording& recording,
                   std::size_t index) {
  const io::RecordedFrame& entry = recording.frames[index];
  hal::Frame frame{io::readPng(io::framePath(dir, entry)), recording.encoding, {}};
  frame.metadata = {index, entry.timestampUs, entry.exposureUs, entry.gain, entry.ledOn};
  return frame;
}

// The white paper's linear level (1 = full scale) at the window centre in an LED-on frame: the
// rig's sensor response (full scale per W / (m^2 sr) s) times the paper's radiance.
double paperLevel(const sim::FrameTruth& t, double paperAlbedo) {
  return sim::RigParams{}.sensorResponse * t.exposureUs * 1e-6 * paperAlbedo / std::numbers::pi *
         t.ledIrradiance;
}

// How many LED-on frames the arm does not cover were rejected as window_occluded, of how many.
std::pair<int, int> falseOcclusions(const RecordingResult& result, const sim::SweepTruth& truth) {
  int rejected = 0, clear = 0;
  for (std::size_t i = 0; i < truth.frames.size(); ++i) {
    if (!truth.frames[i].ledOn || truth.frames[i].occluded) continue;
    ++clear;
    if (result.outcomes[i].rejectReason == RejectReason::WindowOccluded) {
      ++rejected;
      ADD_FAILURE() << "frame " << i << ": " << result.outcomes[i].detail;
    }
  }
  return {rejected, clear};
}

TEST(FramePipelineGate, DarkWhiteReferencesOfAFrameExposedForTheHighlightAreNoOccluder) {
  const auto dir = simulate(kSteel, kDarkSlice, realisticUnblurred(0.0), 24);
  // 24 frames a sweep leave each LED-on frame 15 deg of azimuth from its LED-off frames, where the
  // steel's room light changes: room_light_unseen (another gate) would take some.
  PipelineSettings settings;
  settings.maxRoomLightDistanceMm = 0.0;
  const RecordingResult result = processRecording(dir, settings);
  const sim::SweepTruth truth = sim::readTruth(dir);
  const double paperAlbedo = io::readRecording(dir).target.paperAlbedo.mean();
  int ledOn = 0;
  double brightestPaper = 0.0;
  for (std::size_t i = 0; i < truth.frames.size(); ++i) {
    if (!truth.frames[i].ledOn) continue;
    ++ledOn;
    brightestPaper = std::max(brightestPaper, paperLevel(truth.frames[i], paperAlbedo));
    const FrameOutcome& o = result.outcomes[i];
    EXPECT_EQ(o.kind, FrameOutcome::Kind::Sample) << "frame " << i << ": " << o.detail;
  }
  // The case of the issue: the references this dark, where 3 x 3 points of them disagreed by
  // 8-15 % from noise alone.
  EXPECT_LT(brightestPaper, 0.02);
  EXPECT_EQ(result.bins.filledCount(), ledOn);
}

TEST(FramePipelineGate, NoUnoccludedFrameOfTheAnisotropicMaterialsIsTakenForOccluded) {
  // The built-in anisotropic materials, at the slice whose references are darkest.
  for (const char* material :
       {"brushed-aluminium", "brushed-steel-30", "brushed-brass-120", "copper-ggx-15",
        "satin-red-90", "satin-blue-45", "ward-gold-60", "velvet-green-20"}) {
    SCOPED_TRACE(material);
    const auto dir = simulate(material, kDarkSlice, realisticUnblurred(0.0), 12);
    const auto [rejected, clear] = falseOcclusions(processRecording(dir), sim::readTruth(dir));
    EXPECT_EQ(clear, 6);
    EXPECT_LE(rejected, clear / 10);
  }
}

TEST(FramePipelineGate, TheLightArmOverTheWhiteReferencesIsStillCaught) {
  // A dark session (the noise allowance at its widest) and a bright one.
  for (const char* material : {kSteel, "satin-red-90"}) {
    SCOPED_TRACE(material);
    const auto dir = simulate(material, kDarkSlice, realisticUnblurred(1.0), 12);
    const RecordingResult result = processRecording(dir);
    const sim::SweepTruth truth = sim::readTruth(dir);
    int located = 0;
    for (std::size_t i = 0; i < truth.frames.size(); ++i) {
      const FrameOutcome& o = result.outcomes[i];
      if (!truth.frames[i].ledOn) continue;
      ASSERT_TRUE(truth.frames[i].occluded) << "frame " << i;
      EXPECT_EQ(o.kind, FrameOutcome::Kind::Rejected) << "frame " << i;
      // The arm may hide too many markers first; a frame that got past the pose is the gate's.
      if (o.rejectReason == RejectReason::TooFewMarkers ||
          o.rejectReason == RejectReason::PoseResidual)
        continue;
      ++located;
      EXPECT_EQ(o.rejectReason, RejectReason::WindowOccluded) << "frame " << i << ": " << o.detail;
    }
    EXPECT_GE(located, 3) << "too few frames reached the gate: the test shows nothing";
  }
}

TEST(FramePipelineGate, ReferencesTheLightFitCannotUseAreRejectedWithTheFitsReason) {
  // The ideal rig's frames, read against a target whose white references are all one wide strip
  // of the white band under the window (still white paper in the frames): its quarters lie on one
  // line, so the fit is refused, and the frame is rejected saying why.
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulate("satin-red-90", slice, sim::RigParams::ideal(), 2);
  const io::Recording recording = io::readRecording(dir);
  vision::TargetGeometry target = recording.target;
  const vision::RectMm& window = recording.target.window;
  const vision::RectMm strip{window.xMinMm + 2.0, window.yMinMm - 9.0, window.xMaxMm + 10.0,
                             window.yMinMm - 3.0};
  for (vision::Patch& patch : target.patches)
    if (patch.kind == vision::PatchKind::White) patch.rect = strip;
  FramePipeline pipeline(target, recording.camera);
  pipeline.setAmbientFrame(frameAt(dir, recording, 1));
  const FrameOutcome outcome = pipeline.process(frameAt(dir, recording, 0), slice);
  EXPECT_EQ(outcome.rejectReason, RejectReason::WindowOccluded);
  EXPECT_NE(outcome.detail.find("light fit: the reference observations lie on one line"),
            std::string::npos)
      << outcome.detail;
}

}  // namespace
}  // namespace slicecap::capture
