// The capture pipeline on virtual-rig recordings: angles and samples against truth.json, the
// gate's reasons, bad input as counted rejections or errors naming the input.
#include "slicecap/capture/frame_pipeline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>
#include <nlohmann/json.hpp>

#include "../support/bracket_rig.hpp"
#include "../support/test_support.hpp"
#include "slicecap/capture/planar_pose.hpp"
#include "slicecap/capture/recording_processor.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/simulate.hpp"

namespace slicecap::capture {
namespace {

constexpr const char* kMaterial = "ward:diffuse=0.3,0.2,0.1,specular=0.2,ax=0.2,ay=0.3,tangent=30";

// A short sweep (8 frames: 4 with the LED on) written to a fresh directory.
std::filesystem::path simulate(const SliceId& slice, sim::RigParams rig, int frames = 8,
                               const std::string& material = kMaterial) {
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

hal::Frame frameOf(const std::filesystem::path& dir, std::size_t index) {
  const io::Recording recording = io::readRecording(dir);
  const io::RecordedFrame& entry = recording.frames[index];
  hal::Frame frame{io::readPng(io::framePath(dir, entry)), recording.encoding, {}};
  frame.metadata = {index, entry.timestampUs, entry.exposureUs, entry.gain, entry.ledOn};
  return frame;
}

TEST(FramePipeline, IdealSweepMatchesTruthInViewAnglesAndBrdf) {
  for (const SliceId& slice :
       {SliceId{SliceKind::Axial, {30, 30}}, SliceId{SliceKind::Diagonal, {75, 30}}}) {
    SCOPED_TRACE(toString(slice));
    // 16-bit linear frames: noise-free 8-bit sRGB would add a systematic quantisation error of a
    // few percent in the dark blue channel (nothing dithers it).
    sim::RigParams rig = sim::RigParams::ideal();
    rig.encoding = PixelEncoding::Linear16;
    // No room light: with 8 frames the LED-off neighbour is 45 deg away along the sweep, and the
    // anisotropic material's reflection of the ceiling differs there (a 48-frame sweep has 7.5).
    rig.ambientIrradiance = 0.0;
    const auto dir = simulate(slice, rig);
    const RecordingResult result = processRecording(dir);
    const sim::SweepTruth truth = sim::readTruth(dir);
    ASSERT_EQ(result.outcomes.size(), truth.frames.size());
    int samples = 0;
    for (std::size_t i = 0; i < truth.frames.size(); ++i) {
      const FrameOutcome& o = result.outcomes[i];
      const sim::FrameTruth& t = truth.frames[i];
      if (!t.ledOn) {
        EXPECT_EQ(o.kind, FrameOutcome::Kind::Ambient);
        continue;
      }
      ASSERT_EQ(o.kind, FrameOutcome::Kind::Sample) << o.rejectReason << ": " << o.detail;
      ++samples;
      EXPECT_LT(angleBetweenDeg(o.sample->view, t.view), 0.2);
      EXPECT_NEAR(o.measurement.cameraDistanceMm, t.cameraDistanceMm, 1.0);
      EXPECT_LT(o.measurement.poseResidualPx, 0.5);
      // The ideal rig's light is exactly at the nominal direction.
      EXPECT_LT(angleBetweenDeg(*o.measurement.nominalLight, t.light), 0.2);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(o.sample->value[c], t.brdf[c], 0.03 * t.brdf[c]) << "channel " << c;
    }
    EXPECT_EQ(samples, 4);
    EXPECT_EQ(result.bins.filledCount(), 4);
  }
}

// Every cell of the window is a sample at its own directions: toward the true camera and LED
// from the cell's centre, with the material's BRDF there (the point-light model's irradiance at
// the cell, not at the window centre). The cells are spread over the window, so their directions
// differ from the centre's by degrees: a cell read at the centre's directions would miss by that.
TEST(FramePipeline, EachWindowCellIsASampleAtItsOwnDirections) {
  const SliceId slice{SliceKind::Diagonal, {75, 75}};
  sim::RigParams rig = sim::RigParams::ideal();
  rig.encoding = PixelEncoding::Linear16;
  rig.ambientIrradiance = 0.0;
  const auto dir = simulate(slice, rig, 4);
  const RecordingResult result = processRecording(dir);
  const sim::SweepTruth truth = sim::readTruth(dir);
  const auto material = sim::loadMaterial(kMaterial);
  int checked = 0;
  for (std::size_t i = 0; i < truth.frames.size(); ++i) {
    const sim::FrameTruth& t = truth.frames[i];
    if (!t.ledOn) continue;
    const FrameOutcome& o = result.outcomes[i];
    ASSERT_EQ(o.kind, FrameOutcome::Kind::Sample) << o.rejectReason << ": " << o.detail;
    ASSERT_TRUE(o.sample->cells);
    const WindowCells& cells = *o.sample->cells;
    ASSERT_EQ(cells.cellsPerSide, PipelineSettings{}.windowCellsPerSide);
    ASSERT_EQ(cells.cells.size(), std::size_t(cells.cellsPerSide * cells.cellsPerSide));
    const Eigen::Vector3d camera = t.pose.cameraCentreMm();
    double spreadDeg = 0.0;
    for (std::size_t k = 0; k < cells.cells.size(); ++k) {
      SCOPED_TRACE("frame " + std::to_string(i) + " cell " + std::to_string(k));
      const CellSample& cell = cells.cells[k];
      const auto [x, y] = cellCentreMm(cells, int(k));
      const Eigen::Vector3d point{x, y, 0.0};
      EXPECT_FALSE(cell.clipped);
      EXPECT_LT(angleBetweenDeg(cell.view, vision::directionFrom(point, camera)), 0.2);
      EXPECT_LT(angleBetweenDeg(cell.light, vision::directionFrom(point, t.lightMm)), 0.2);
      spreadDeg = std::max(spreadDeg, angleBetweenDeg(cell.view, o.sample->view));
      const Rgb truthHere =
          material->evaluate(toUnitVector(cell.light), toUnitVector(cell.view));
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(cell.value[c], truthHere[c], 0.04 * truthHere[c] + 1e-4) << "channel " << c;
    }
    EXPECT_GT(spreadDeg, 2.0);
    ++checked;
  }
  EXPECT_EQ(checked, 2);
  // What the cells cost the journal per sample (docs/reliability.md states it): the records with
  // cells against the same samples without.
  const auto root = test::freshTempDir();
  std::uintmax_t withCells = 0, without = 0;
  for (bool keepCells : {true, false}) {
    const std::string id = keepCells ? "cells" : "centres";
    SessionStore store = SessionStore::create(root, id, "m");
    for (const FrameOutcome& o : result.outcomes)
      if (o.sample) {
        FrameSample sample = *o.sample;
        if (!keepCells) sample.cells.reset();
        store.recordSample(slice, sample);
      }
    (keepCells ? withCells : without) = std::filesystem::file_size(root / id / "journal");
  }
  const double perSample = double(withCells - without) / checked;
  std::cout << "journal: " << perSample << " bytes of cells per sample, "
            << double(without) / checked << " without\n";
  EXPECT_LT(perSample, 6000.0);
}

TEST(FramePipeline, GateCountsElevationOffTooFewMarkersAndBadFrames) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulate(slice, sim::RigParams::ideal(), 2);
  const io::Recording recording = io::readRecording(dir);
  FramePipeline pipeline(recording.target, recording.camera);
  pipeline.setAmbientFrame(frameOf(dir, 1));
  const hal::Frame good = frameOf(dir, 0);

  // Swept at 30 deg, processed as a 75 deg slice: the camera is 45 deg off.
  const FrameOutcome off = pipeline.process(good, {SliceKind::Axial, {30, 75}});
  EXPECT_EQ(off.rejectReason, RejectReason::ElevationOff);
  ASSERT_TRUE(off.viewElevationErrorDeg.has_value());
  EXPECT_NEAR(*off.viewElevationErrorDeg, -45.0, 1.0);

  // A blank frame (no target in view) and one with all but the top rows blanked. Live, the
  // search of a lost target is spread over frames: each such frame is a counted
  // RejectReason::DetectionDeferred; with no budget every pass runs at once and finds too few.
  hal::Frame blank = good;
  std::fill(blank.image.samples.begin(), blank.image.samples.end(), 128);
  EXPECT_EQ(pipeline.process(blank, slice).rejectReason, RejectReason::DetectionDeferred);
  hal::Frame cut = good;
  std::fill(cut.image.samples.begin() + cut.image.samples.size() / 8, cut.image.samples.end(), 128);
  const FrameOutcome few = pipeline.process(cut, slice);
  EXPECT_EQ(few.rejectReason, RejectReason::DetectionDeferred);
  EXPECT_LT(few.measurement.markerCount, 4);
  EXPECT_LE(few.measurement.detectionWorkPx, MarkerDetectorSettings{}.frameBudgetPx);
  PipelineSettings unlimited;
  unlimited.detector.frameBudgetPx = std::numeric_limits<double>::infinity();
  FramePipeline everything(recording.target, recording.camera, unlimited);
  everything.setAmbientFrame(frameOf(dir, 1));
  EXPECT_EQ(everything.process(blank, slice).rejectReason, RejectReason::TooFewMarkers);
  EXPECT_EQ(everything.process(cut, slice).rejectReason, RejectReason::TooFewMarkers);

  hal::Frame small = good;
  small.image.width /= 2;
  small.image.samples.resize(small.image.samples.size() / 2);
  const FrameOutcome bad = pipeline.process(small, slice);
  EXPECT_EQ(bad.rejectReason, RejectReason::BadFrame);
  EXPECT_NE(bad.detail.find("expected 1280 x 720"), std::string::npos) << bad.detail;

  // The rejections left no state behind: the same good frame is still a sample.
  EXPECT_EQ(pipeline.process(good, slice).kind, FrameOutcome::Kind::Sample);
}

TEST(FramePipeline, NoAmbientFrameYetIsRejectedLive) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulate(slice, sim::RigParams::ideal(), 2);
  const io::Recording recording = io::readRecording(dir);
  const FrameProcessor process = makeFramePipeline(recording.target, recording.camera);
  EXPECT_EQ(process(frameOf(dir, 0), slice).rejectReason, RejectReason::NoAmbientFrame);
  EXPECT_EQ(process(frameOf(dir, 1), slice).kind, FrameOutcome::Kind::Ambient);
  EXPECT_EQ(process(frameOf(dir, 0), slice).kind, FrameOutcome::Kind::Sample);
}

// A frame the pipeline rejects as RejectReason::BadFrame (here half the size the camera gives) is
// no room-light term either: not as the LED-off frame before (live or offline) nor as the one after
// (offline).
TEST(FramePipeline, AnLedOffFrameOfTheWrongSizeIsNoRoomLightTerm) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulate(slice, sim::RigParams::ideal(), 8);
  const io::Recording recording = io::readRecording(dir);
  // Frame 3 (LED off) at half resolution: every second pixel of every second row.
  const hal::Frame full = frameOf(dir, 3);
  ASSERT_FALSE(full.metadata.ledOn);
  hal::Frame half = full;
  half.image.width = full.image.width / 2;
  half.image.height = full.image.height / 2;
  half.image.samples.clear();
  for (int y = 0; y < half.image.height; ++y)
    for (int x = 0; x < half.image.width; ++x)
      for (int c = 0; c < full.image.channels; ++c)
        half.image.samples.push_back(full.image.at(2 * x, 2 * y, c));

  FramePipeline live(recording.target, recording.camera);
  live.setAmbientFrame(half);
  EXPECT_TRUE(live.ambientTermsFor(frameOf(dir, 2).metadata.timestampUs).empty());
  EXPECT_EQ(live.process(frameOf(dir, 2), slice).rejectReason, RejectReason::NoAmbientFrame);
  EXPECT_EQ(live.process(half, slice).rejectReason, RejectReason::BadFrame);
  EXPECT_EQ(live.process(frameOf(dir, 4), slice).rejectReason, RejectReason::NoAmbientFrame);

  FramePipeline offline(recording.target, recording.camera);
  offline.setAmbientFrame(frameOf(dir, 1));
  offline.setFollowingAmbientFrame(half);
  const auto terms = offline.ambientTermsFor(frameOf(dir, 2).metadata.timestampUs);
  EXPECT_EQ(terms.size(), 1u);
  EXPECT_EQ(terms.at(0).frame->metadata.timestampUs, frameOf(dir, 1).metadata.timestampUs);

  // processRecording: the frame's PNG at half size gives every other frame the outcome it has
  // when that PNG is corrupt (both are RejectReason::BadFrame).
  const auto victim = io::framePath(dir, recording.frames[3]);
  io::writePng(victim, half.image);
  const RecordingResult wrongSize = processRecording(dir);
  std::filesystem::resize_file(victim, std::filesystem::file_size(victim) / 2);
  const RecordingResult corrupt = processRecording(dir);
  EXPECT_EQ(wrongSize.outcomes[3].rejectReason, RejectReason::BadFrame);
  EXPECT_EQ(corrupt.outcomes[3].rejectReason, RejectReason::BadFrame);
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    if (i == 3) continue;
    SCOPED_TRACE("frame " + std::to_string(i));
    ASSERT_EQ(wrongSize.outcomes[i].kind, corrupt.outcomes[i].kind);
    if (!corrupt.outcomes[i].sample) continue;
    for (int c = 0; c < 3; ++c)
      EXPECT_DOUBLE_EQ(wrongSize.outcomes[i].sample->value[c],
                       corrupt.outcomes[i].sample->value[c]);
  }
}

// Offline HDR: an LED-on frame whose own LED-off frame was not located takes its room light from
// another level's located LED-off frames around it, weighted linearly in time, each with its pose;
// one the pipeline would reject as bad_frame is left out; an empty list ends the stand-ins.
TEST(FramePipeline, AnUnlocatedLedOffFrameGivesWayToStandInsAroundTheLedOnFrame) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulate(slice, sim::RigParams::ideal(), 4);
  const io::Recording recording = io::readRecording(dir);
  PipelineSettings settings;
  settings.poseAmbientFrames = true;
  FramePipeline pipeline(recording.target, recording.camera, settings);
  hal::Frame dark = frameOf(dir, 1);  // LED off and black: no marker to locate
  std::fill(dark.image.samples.begin(), dark.image.samples.end(), std::uint16_t{0});
  pipeline.setAmbientFrame(dark);
  const std::int64_t ledOnUs = frameOf(dir, 2).metadata.timestampUs;
  ASSERT_EQ(pipeline.ambientTermsFor(ledOnUs).size(), 1u);
  EXPECT_FALSE(pipeline.ambientTermsFor(ledOnUs).at(0).pose);

  const auto standIn = [&](std::int64_t timeUs, double xMm) {
    LocatedAmbientFrame f{frameOf(dir, 3), {}};
    f.frame.metadata.timestampUs = timeUs;
    f.pose.translationMm = {xMm, 0.0, 500.0};
    return f;
  };
  LocatedAmbientFrame wrongSize = standIn(ledOnUs - 50'000, 3.0);
  wrongSize.frame.image.width /= 2;
  pipeline.setStandInAmbientFrames({standIn(ledOnUs - 40'000, 1.0), standIn(ledOnUs - 10'000, 2.0),
                                    standIn(ledOnUs + 30'000, 4.0), wrongSize});
  const std::vector<AmbientTerm> terms = pipeline.ambientTermsFor(ledOnUs);
  ASSERT_EQ(terms.size(), 2u);
  EXPECT_EQ(terms[0].frame->metadata.timestampUs, ledOnUs - 10'000);
  EXPECT_EQ(terms[1].frame->metadata.timestampUs, ledOnUs + 30'000);
  EXPECT_DOUBLE_EQ(terms[0].weight, 0.75);
  EXPECT_DOUBLE_EQ(terms[1].weight, 0.25);
  ASSERT_TRUE(terms[0].pose && terms[1].pose);
  EXPECT_DOUBLE_EQ(terms[0].pose->translationMm.x(), 2.0);
  EXPECT_DOUBLE_EQ(terms[1].pose->translationMm.x(), 4.0);
  // Before the first stand-in (the bad one left out), the nearest alone.
  const std::vector<AmbientTerm> early = pipeline.ambientTermsFor(ledOnUs - 45'000);
  ASSERT_EQ(early.size(), 1u);
  EXPECT_EQ(early[0].frame->metadata.timestampUs, ledOnUs - 40'000);

  pipeline.setStandInAmbientFrames({});
  ASSERT_EQ(pipeline.ambientTermsFor(ledOnUs).size(), 1u);
  EXPECT_EQ(pipeline.ambientTermsFor(ledOnUs).at(0).frame->metadata.timestampUs,
            dark.metadata.timestampUs);
}

// A realistic HDR sweep of a sharp metal: the short level's LED-off frames are too dark to locate
// (its markers a few codes above black), so their room light was read at the LED-on frame's pixels
// after the hand moved, and misread references rejected frames on the highlight. processRecording
// now gives each short LED-on frame the long level's located LED-off frames around it.
TEST(FramePipeline, AShortExposuresRoomLightComesFromTheLongLevelsLocatedLedOffFrames) {
  const SliceId slice{SliceKind::Diagonal, {30, 30}};
  sim::RigParams rig = sim::RigParams::realistic();
  rig.maxExposureLevels = 2;
  const auto dir =
      simulate(slice, rig, 16, "ward:diffuse=0.02,specular=0.9,ax=0.04,ay=0.3,tangent=0");
  const io::Recording recording = io::readRecording(dir);
  struct Seen {
    std::size_t index;
    std::vector<std::pair<std::int64_t, bool>> terms;  // timestamp, located
  };
  std::vector<Seen> shortLedOn;
  const RecordingResult result = processRecording(
      dir, {}, [&](const hal::Frame& frame, const FrameOutcome&, const std::vector<AmbientTerm>& t) {
        const io::RecordedFrame& entry = recording.frames.at(frame.metadata.sequence);
        if (!entry.ledOn || entry.exposureLevel.value_or(0) != 1) return;
        Seen seen{frame.metadata.sequence, {}};
        for (const AmbientTerm& term : t)
          seen.terms.emplace_back(term.frame->metadata.timestampUs, term.pose.has_value());
        shortLedOn.push_back(std::move(seen));
      });
  ASSERT_EQ(result.exposureLevels, 2);
  std::set<std::int64_t> locatedLong;
  int unlocatedShort = 0;
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    const io::RecordedFrame& entry = recording.frames[i];
    if (entry.ledOn || result.outcomes[i].kind != FrameOutcome::Kind::Ambient) continue;
    const bool located = result.outcomes[i].measurement.pose.has_value();
    if (entry.exposureLevel.value_or(0) == 0 && located) locatedLong.insert(entry.timestampUs);
    if (entry.exposureLevel.value_or(0) == 1 && !located) ++unlocatedShort;
  }
  ASSERT_GT(unlocatedShort, 0) << "the case under test: short LED-off frames not located";
  ASSERT_GE(locatedLong.size(), 4u);
  ASSERT_GE(shortLedOn.size(), 8u);
  for (const Seen& seen : shortLedOn) {
    SCOPED_TRACE("frame " + std::to_string(seen.index));
    ASSERT_FALSE(seen.terms.empty());
    for (const auto& [timeUs, located] : seen.terms) {
      EXPECT_TRUE(located);
      EXPECT_TRUE(locatedLong.count(timeUs)) << "a term not from the long level: " << timeUs;
    }
  }
}

// The model camera (the IMX708's tone curve and colour gains, read and shot noise) held still at
// a 75/75 view, as live HDR sweeps it: a long exposure metered on the target and a short one at
// 1/16 of it, the second level of `hdr_levels = 2`. The short frame puts the paper a few codes
// above black, and the markers are foreshortened 4 x at 75 deg: the coarse passes that re-acquire
// a lost target within a frame's budget miss them (measured live before the long level's pose was
// handed on: 0.58 of the short LED-on frames located over 13 sweeps, 4 of 57 in the worst,
// docs/results/2026-12-03-hdr-tracking.md).
struct DarkHdrFrames {
  hal::Frame longFrame, shortFrame;
  vision::Pose truth;
  vision::CameraModel camera = vision::defaultSimulatedCamera();
  vision::TargetGeometry target = vision::defaultTarget();

  // The long frame `kLongRepeats` times, a frame period apart (the live loop's budget spreads
  // the first search of the target over frames), then the short frame after them.
  static constexpr int kLongRepeats = 8;
  std::vector<hal::Frame> sequence() const {
    std::vector<hal::Frame> frames(kLongRepeats, longFrame);
    frames.push_back(shortFrame);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      frames[i].metadata.sequence = i;
      frames[i].metadata.timestampUs = longFrame.metadata.timestampUs + std::int64_t(i) * 33'333;
    }
    return frames;
  }
};

const DarkHdrFrames& darkHdrFrames() {
  static const DarkHdrFrames frames = [] {
    DarkHdrFrames f;
    const double t = 75.0 * M_PI / 180.0;
    f.truth = vision::lookAtPose({300.0 * std::sin(t), 0.0, 300.0 * std::cos(t)}, {0, 0, 0},
                                 {0, 1, 0});
    const auto renderer = std::make_shared<sim::FrameRenderer>(
        f.camera, f.target, sim::loadMaterial(kMaterial), sim::RigParams::ideal());
    // The LED at 75 deg too, a quarter turn round (off the mirror direction: the exposure is
    // metered on the paper, as the daemon meters a sweep's first position).
    const Eigen::Vector3d lightMm{0.0, 300.0 * std::sin(t), 300.0 * std::cos(t)};
    test::BracketRig rig(std::make_shared<test::StillScene>(renderer, f.truth, lightMm),
                         hal::SensorModel{});
    const double longUs = rig.meteredExposureUs();
    std::vector<hal::Frame> taken = rig.take({{longUs, 1.0}, {longUs / 16.0, 1.0}});
    f.longFrame = std::move(taken[0]);
    f.shortFrame = std::move(taken[1]);
    for (hal::Frame* frame : {&f.longFrame, &f.shortFrame})
      frame->metadata.ledOn = true;  // the camera cannot know: whoever drives the LED says
    f.longFrame.metadata.exposureLevel = 0;
    f.shortFrame.metadata.exposureLevel = 1;
    return f;
  }();
  return frames;
}

PipelineSettings hdrWithoutRoomLight() {
  PipelineSettings settings;
  settings.hdr = true;
  settings.requireAmbient = false;  // the still rig's LED stays on
  return settings;
}

// The long level's latest location after its frames of `frames` until it has one (the live
// budget spreads the first search over frames); none if it found none.
std::optional<TimedPose> longLevelLocation(const DarkHdrFrames& f,
                                           const std::vector<hal::Frame>& frames) {
  const SliceId slice{SliceKind::Diagonal, {75, 75}};
  FramePipeline longLevel(f.target, f.camera, hdrWithoutRoomLight());
  for (int i = 0; i < DarkHdrFrames::kLongRepeats && !longLevel.latestLocation(); ++i)
    longLevel.process(frames[std::size_t(i)], slice);
  return longLevel.latestLocation();
}

TEST(FramePipeline, AShortLevelsDarkFrameIsSearchedAroundTheLongLevelsLatestPose) {
  const DarkHdrFrames& f = darkHdrFrames();
  const SliceId slice{SliceKind::Diagonal, {75, 75}};
  const std::vector<hal::Frame> frames = f.sequence();
  const hal::Frame& shortFrame = frames.back();
  const std::optional<TimedPose> location = longLevelLocation(f, frames);
  ASSERT_TRUE(location) << "the long frame was not located";

  // A pipeline without a recent pose re-acquires the target over frames, within each frame's
  // budget: still, the short frame takes several (measured: 4); a moving sweep's short level,
  // whose blocks of frames are a few frames long, mostly never caught up.
  FramePipeline alone(f.target, f.camera, hdrWithoutRoomLight());
  const FrameOutcome first = alone.process(shortFrame, slice);
  EXPECT_FALSE(first.measurement.pose) << "the case under test: " << first.detail;
  EXPECT_EQ(first.rejectReason, RejectReason::DetectionDeferred) << first.detail;
  EXPECT_FALSE(alone.latestLocation());

  // Around the long frame's pose, within the same budget, it is, in its first frame.
  FramePipeline tracked(f.target, f.camera, hdrWithoutRoomLight());
  tracked.trackFrom(*location);
  const FrameOutcome outcome = tracked.process(shortFrame, slice);
  ASSERT_TRUE(outcome.measurement.pose) << outcome.detail;
  EXPECT_LT((outcome.measurement.pose->cameraCentreMm() - f.truth.cameraCentreMm()).norm(), 3.0);
  // Its own location now, which an older one does not replace.
  ASSERT_TRUE(tracked.latestLocation());
  EXPECT_EQ(tracked.latestLocation()->timestampUs, shortFrame.metadata.timestampUs);
  tracked.trackFrom(*location);
  EXPECT_EQ(tracked.latestLocation()->timestampUs, shortFrame.metadata.timestampUs);
}

// A pose the short level's search dropped after missing with it is not taken back when the long
// level's location is older; a newer one is.
TEST(FramePipeline, AShortLevelTakesOnlyALocationNewerThanItsLatest) {
  const DarkHdrFrames& f = darkHdrFrames();
  const SliceId slice{SliceKind::Diagonal, {75, 75}};
  const std::vector<hal::Frame> frames = f.sequence();
  const std::optional<TimedPose> older = longLevelLocation(f, frames);
  ASSERT_TRUE(older);

  FramePipeline shortLevel(f.target, f.camera, hdrWithoutRoomLight());
  shortLevel.trackFrom(*older);
  ASSERT_TRUE(shortLevel.process(frames.back(), slice).measurement.pose);
  const std::int64_t ownUs = frames.back().metadata.timestampUs;
  // The target lost: black frames until the search drops its pose.
  hal::Frame black = frames.back();
  std::fill(black.image.samples.begin(), black.image.samples.end(), std::uint16_t{0});
  const int misses = hdrWithoutRoomLight().detector.trackingPatienceFrames + 2;
  for (int k = 1; k <= misses; ++k) {
    black.metadata.timestampUs = ownUs + k * 33'333;
    shortLevel.process(black, slice);
  }
  ASSERT_FALSE(shortLevel.latestLocation());
  shortLevel.trackFrom(*older);
  EXPECT_FALSE(shortLevel.latestLocation()) << "an older location than its own was taken back";
  TimedPose newer = *older;
  newer.timestampUs = ownUs + (misses + 1) * 33'333;
  shortLevel.trackFrom(newer);
  ASSERT_TRUE(shortLevel.latestLocation());
  EXPECT_EQ(shortLevel.latestLocation()->timestampUs, newer.timestampUs);
}

// The live loop's processor (one pipeline per level) hands the longest level's location on.
TEST(FramePipeline, TheLiveProcessorSearchesAShortLevelsFrameAroundTheLongLevelsPose) {
  const DarkHdrFrames& f = darkHdrFrames();
  const SliceId slice{SliceKind::Diagonal, {75, 75}};
  const FrameProcessor process = makeFramePipeline(f.target, f.camera, hdrWithoutRoomLight());
  const std::vector<hal::Frame> frames = f.sequence();
  bool longLocated = false;
  for (int i = 0; i < DarkHdrFrames::kLongRepeats; ++i)
    longLocated = process(frames[std::size_t(i)], slice).measurement.pose.has_value();
  ASSERT_TRUE(longLocated);
  const FrameOutcome outcome = process(frames.back(), slice);
  ASSERT_TRUE(outcome.measurement.pose) << outcome.detail;
  EXPECT_EQ(outcome.kind, FrameOutcome::Kind::Sample) << outcome.detail;
}

// A short level's cell darker than its noise: most of its pixels at code 0 (the processed
// stream cannot go below black). The area's censored mean (censored_mean.cpp) then reads it
// below 0, as the light's best estimate may be; the cell's level (how exposed it was) must still
// be a level, not a negative fraction: the journal checks it, and refused the whole sample as a
// bad frame (seen in a daemon HDR session on the camera model under load).
TEST(FramePipeline, AnHdrCellBelowItsNoiseIsRecordedAsDark) {
  const DarkHdrFrames& f = darkHdrFrames();
  const SliceId slice{SliceKind::Diagonal, {75, 75}};
  const std::vector<hal::Frame> frames = f.sequence();
  const std::optional<TimedPose> location = longLevelLocation(f, frames);
  ASSERT_TRUE(location) << "the long frame was not located";
  hal::Frame dark = frames.back();
  ASSERT_EQ(dark.encoding, PixelEncoding::Srgb8) << "the case under test: the processed stream";
  // The window's image: 1 pixel in 8 at code 1 (a light of about -1.2 sigma), the rest at 0.
  const vision::RectMm& w = f.target.window;
  double minX = dark.image.width, minY = dark.image.height, maxX = 0.0, maxY = 0.0;
  for (const double x : {w.xMinMm, w.xMaxMm})
    for (const double y : {w.yMinMm, w.yMaxMm}) {
      const std::optional<Eigen::Vector2d> px = f.camera.project(f.truth.toCamera({x, y, 0.0}));
      ASSERT_TRUE(px);
      minX = std::min(minX, px->x()), maxX = std::max(maxX, px->x());
      minY = std::min(minY, px->y()), maxY = std::max(maxY, px->y());
    }
  int count = 0;
  for (int y = int(minY) + 2; y < int(maxY) - 2; ++y)
    for (int x = int(minX) + 2; x < int(maxX) - 2; ++x)
      for (int c = 0; c < 3; ++c) dark.image.at(x, y, c) = (++count % 8 == 0) ? 1 : 0;

  FramePipeline tracked(f.target, f.camera, hdrWithoutRoomLight());
  tracked.trackFrom(*location);
  const FrameOutcome outcome = tracked.process(dark, slice);
  ASSERT_EQ(outcome.kind, FrameOutcome::Kind::Sample) << outcome.detail;
  ASSERT_TRUE(outcome.sample && outcome.sample->hdr);
  bool belowZero = false;
  for (const HdrCell& cell : outcome.sample->hdr->cells) {
    belowZero = belowZero || cell.radiance.maxChannel() < 0.0;
    EXPECT_GE(cell.level, 0.0);
  }
  EXPECT_TRUE(belowZero) << "the case under test: a cell read below 0";
  SessionStore store = SessionStore::create(test::freshTempDir(), "dark-cell", "test");
  EXPECT_NO_THROW(store.recordSample(slice, *outcome.sample));
}

// processRecording does the same, level by level: the short level's frames are searched around
// the long level's location before each. As live (`--ambient previous`, the live loop's budget)
// the short frame needs it; offline without a budget the whole-frame passes find this still frame
// anyway, and the check there is that the hand-on loses nothing.
TEST(FramePipeline, ARecordingsShortLevelIsSearchedAroundTheLongLevelsPoseOfflineAsLive) {
  const DarkHdrFrames& f = darkHdrFrames();
  const auto dir = test::freshTempDir() / "dark-hdr";
  std::filesystem::create_directories(dir);
  io::Recording recording;
  recording.camera = f.camera;
  recording.target = f.target;
  recording.slice = io::RecordedSlice{SliceId{SliceKind::Diagonal, {75, 75}}};
  recording.decoding = io::RecordedDecoding{};  // sRGB: finding markers needs no curve
  const std::vector<hal::Frame> frames = f.sequence();
  for (const hal::Frame& frame : frames) {
    io::RecordedFrame entry;
    entry.file = "frame-" + std::to_string(recording.frames.size()) + ".png";
    entry.timestampUs = frame.metadata.timestampUs;
    entry.exposureUs = frame.metadata.exposureUs;
    entry.gain = frame.metadata.gain;
    entry.exposureLevel = frame.metadata.exposureLevel;
    io::writePng(dir / entry.file, frame.image);
    recording.frames.push_back(entry);
  }
  io::writeRecordingManifest(dir, recording);
  for (const bool twoSided : {true, false}) {
    SCOPED_TRACE(twoSided ? "offline" : "as live (--ambient previous)");
    PipelineSettings settings;
    settings.offlineTwoSidedAmbient = twoSided;
    const RecordingResult result = processRecording(dir, settings);
    ASSERT_EQ(result.exposureLevels, 2);
    EXPECT_TRUE(result.outcomes[DarkHdrFrames::kLongRepeats - 1].measurement.pose);
    EXPECT_TRUE(result.outcomes.back().measurement.pose) << result.outcomes.back().detail;
  }
}

// A camera may report no exposure for a frame (0: libcamera's uvcvideo, V4L2 under auto
// exposure, a frame from before a lock). Two frames both unknown are taken as equally exposed;
// but with only one of them known, the LED-off frame's room light cannot be put in the LED-on
// frame's units: subtracted as it was, it wiped out the white references ("white references out
// of the image") or was not subtracted at all (a sample that kept the room light).
TEST(FramePipeline, RoomLightOfAFrameOfUnknownExposureIsNotSubtractedFromAKnownOne) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulate(slice, sim::RigParams::ideal(), 4);
  const io::Recording recording = io::readRecording(dir);
  const auto outcomeWith = [&](double offExposureUs, double onExposureUs) {
    FramePipeline pipeline(recording.target, recording.camera);
    hal::Frame off = frameOf(dir, 1), on = frameOf(dir, 2);
    off.metadata.exposureUs = offExposureUs;
    on.metadata.exposureUs = onExposureUs;
    EXPECT_EQ(pipeline.process(off, slice).kind, FrameOutcome::Kind::Ambient);
    return pipeline.process(on, slice);
  };
  const double exposureUs = frameOf(dir, 2).metadata.exposureUs;
  ASSERT_GT(exposureUs, 0.0);
  const FrameOutcome known = outcomeWith(exposureUs, exposureUs);
  ASSERT_EQ(known.kind, FrameOutcome::Kind::Sample) << known.rejectReason << ": " << known.detail;
  const FrameOutcome bothUnknown = outcomeWith(0.0, 0.0);
  ASSERT_EQ(bothUnknown.kind, FrameOutcome::Kind::Sample) << bothUnknown.rejectReason;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(bothUnknown.sample->value[c], known.sample->value[c],
                1e-9 * known.sample->value[c]);
  for (const auto& [off, on] : {std::pair{0.0, exposureUs}, std::pair{exposureUs, 0.0}}) {
    SCOPED_TRACE("LED-off exposure " + std::to_string(off) + " us, LED-on " + std::to_string(on));
    const FrameOutcome mixed = outcomeWith(off, on);
    EXPECT_EQ(mixed.rejectReason, RejectReason::NoAmbientFrame) << mixed.detail;
    EXPECT_NE(mixed.detail.find("exposure"), std::string::npos) << mixed.detail;
  }
}

// requireAmbient = false (slicecapd's led_alternate = false): an LED-off frame that still comes
// (the sweep's first) is not subtracted; it would stand for the room light of the whole sweep.
TEST(FramePipeline, WithoutAmbientRequiredAnLedOffFrameIsNotSubtracted) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = simulate(slice, sim::RigParams::ideal(), 4);
  const io::Recording recording = io::readRecording(dir);
  const auto sampleAfterLedOff = [&](bool requireAmbient, bool ledOffFirst) {
    PipelineSettings settings;
    settings.requireAmbient = requireAmbient;
    FramePipeline pipeline(recording.target, recording.camera, settings);
    if (ledOffFirst) {
      EXPECT_EQ(pipeline.process(frameOf(dir, 1), slice).kind, FrameOutcome::Kind::Ambient);
    }
    const FrameOutcome outcome = pipeline.process(frameOf(dir, 2), slice);
    EXPECT_EQ(outcome.kind, FrameOutcome::Kind::Sample) << outcome.rejectReason;
    return outcome.sample ? outcome.sample->value : Rgb{};
  };
  const Rgb alone = sampleAfterLedOff(false, false);
  const Rgb afterLedOff = sampleAfterLedOff(false, true);
  const Rgb subtracted = sampleAfterLedOff(true, true);
  for (int c = 0; c < 3; ++c) {
    // Not bit-equal: the LED-off frame located the target, so the LED-on one was found by the
    // tracked search (corners a fraction of a pixel apart; measured 0.01 % at most).
    EXPECT_NEAR(afterLedOff[c], alone[c], 3e-4 * alone[c]) << "channel " << c;
    // The room light is there to subtract: else this test could not tell.
    EXPECT_LT(subtracted[c], 0.999 * alone[c]) << "channel " << c;
  }
}

// Median over LED-on frames of the worst channel's relative error against the truth.
double medianSampleError(const std::vector<FrameOutcome>& outcomes, const sim::SweepTruth& truth) {
  std::vector<double> errors;
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    if (outcomes[i].kind != FrameOutcome::Kind::Sample) continue;
    double worst = 0.0;
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(outcomes[i].sample->value[c] - truth.frames[i].brdf[c]) /
                                  truth.frames[i].brdf[c]);
    errors.push_back(worst);
  }
  if (errors.empty()) return 1e9;
  std::sort(errors.begin(), errors.end());
  return errors[errors.size() / 2];
}

TEST(FramePipeline, AmbientFromBothSidesBeatsThePreviousLedOffFrameOnASpecularMaterial) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  sim::RigParams rig = sim::RigParams::ideal();
  rig.encoding = PixelEncoding::Linear16;
  rig.ambientIrradiance = 2.0;  // strong room light, reflected differently along the sweep
  const auto dir = simulate(slice, rig, 24);
  const sim::SweepTruth truth = sim::readTruth(dir);
  const double offline = medianSampleError(processRecording(dir).outcomes, truth);
  // The live loop: each LED-on frame minus the LED-off frame before it, at the same pixels.
  const io::Recording recording = io::readRecording(dir);
  FramePipeline live(recording.target, recording.camera);
  live.setAmbientFrame(frameOf(dir, 1));
  std::vector<FrameOutcome> liveOutcomes;
  for (std::size_t i = 0; i < recording.frames.size(); ++i)
    liveOutcomes.push_back(live.process(frameOf(dir, i), slice));
  const double oneSided = medianSampleError(liveOutcomes, truth);
  EXPECT_LT(offline, 0.5 * oneSided) << "two-sided " << offline << ", one-sided " << oneSided;
  // Seven times the realistic room light and 15 deg steps: the 2 % goal holds on the realistic
  // 48-frame session (docs/results/2026-11-24-capture-accuracy.md); here the residual curvature
  // shows.
  EXPECT_LT(offline, 0.04);
}

TEST(FramePipeline, RealisticSweepRejectsBlurredAndOccludedFramesWithReasons) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  sim::RigParams rig = sim::RigParams::realistic();
  rig.motionBlurFraction = 0.5;
  rig.motionBlurMaxPx = 8.0;
  rig.occlusionFraction = 0.0;
  rig.markersOutOfViewFraction = 0.0;
  const auto dir = simulate(slice, rig, 16);
  const RecordingResult result = processRecording(dir);
  const sim::SweepTruth truth = sim::readTruth(dir);
  int blurredSeen = 0;
  for (std::size_t i = 0; i < truth.frames.size(); ++i) {
    const sim::FrameTruth& t = truth.frames[i];
    const FrameOutcome& o = result.outcomes[i];
    if (!t.ledOn) continue;
    if (t.motionBlurPx > 4.0) {
      ++blurredSeen;
      EXPECT_EQ(o.kind, FrameOutcome::Kind::Rejected)
          << "frame " << i << " blur " << t.motionBlurPx;
    }
    if (t.motionBlurPx == 0.0) {
      ASSERT_EQ(o.kind, FrameOutcome::Kind::Sample) << o.rejectReason << ": " << o.detail;
      EXPECT_LT(angleBetweenDeg(o.sample->view, t.view), 0.2);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(o.sample->value[c], t.brdf[c], 0.05 * t.brdf[c]) << "frame " << i;
    }
  }
  EXPECT_GT(blurredSeen, 0) << "the seed gave no strongly blurred frame: the test shows nothing";
  int rejected = 0;
  for (const auto& [reason, count] : result.rejections)
    rejected += count;
  EXPECT_GE(rejected, blurredSeen);
}

TEST(FramePipeline, CorruptPngIsACountedRejectionAndMissingFieldAnError) {
  const SliceId slice{SliceKind::Diagonal, {30, 30}};
  const auto dir = simulate(slice, sim::RigParams::ideal(), 4);
  const io::Recording recording = io::readRecording(dir);
  const auto victim = io::framePath(dir, recording.frames[2]);
  std::filesystem::resize_file(victim, std::filesystem::file_size(victim) / 2);
  const RecordingResult result = processRecording(dir);
  EXPECT_EQ(result.rejections.at(RejectReason::BadFrame), 1);
  EXPECT_NE(result.outcomes[2].detail.find("frame-00002.png"), std::string::npos)
      << result.outcomes[2].detail;
  EXPECT_EQ(result.outcomes[0].kind, FrameOutcome::Kind::Sample);

  nlohmann::json manifest;
  std::ifstream(dir / "recording.json") >> manifest;
  manifest["frames"][1].erase("exposure_us");
  std::ofstream(dir / "recording.json") << manifest.dump();
  try {
    processRecording(dir);
    FAIL() << "a missing field was accepted";
  } catch (const io::IoError& error) {
    EXPECT_NE(std::string(error.what()).find("exposure_us"), std::string::npos) << error.what();
  }
}

TEST(FramePipeline, ARecordingOfAPointSliceIsAnErrorNamingTheDirectory) {
  // recording.json may say "point" (the slice kind of scattered samples): no sweep has that kind,
  // and its samples fall in no azimuth bin. The recording reader refuses it, naming the file.
  const auto dir = simulate({SliceKind::Diagonal, {30, 30}}, sim::RigParams::ideal(), 2);
  nlohmann::json manifest;
  std::ifstream(dir / "recording.json") >> manifest;
  manifest["slice"]["kind"] = "point";
  std::ofstream(dir / "recording.json") << manifest.dump();
  try {
    processRecording(dir);
    FAIL() << "a point slice was processed";
  } catch (const io::IoError& error) {
    EXPECT_NE(std::string(error.what()).find(dir.string()), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("point"), std::string::npos) << error.what();
  }
}

TEST(PlanarPose, RecoversFrontoParallelAndObliquePosesFromCorners) {
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  const vision::TargetGeometry target = vision::defaultTarget();
  for (const Eigen::Vector3d& centre :
       {Eigen::Vector3d(0.5, 0.3, 300.0), Eigen::Vector3d(150.0, 80.0, 260.0),
        Eigen::Vector3d(-60.0, 40.0, 80.0)}) {
    const vision::Pose truth =
        vision::lookAtPose(centre, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0.3));
    std::vector<PlaneCorrespondence> points;
    for (const auto& m : target.markers)
      for (const auto& c : m.cornersMm)
        if (const auto px = camera.project(truth.toCamera({c.xMm, c.yMm, 0.0})))
          points.push_back({{c.xMm, c.yMm}, *px});
    const auto estimate = estimatePlanarPose(points, camera);
    ASSERT_TRUE(estimate.has_value());
    EXPECT_LT(estimate->residualRmsPx, 1e-6);
    EXPECT_LT((estimate->pose.cameraCentreMm() - centre).norm(), 1e-4);
  }
  EXPECT_FALSE(estimatePlanarPose(std::vector<PlaneCorrespondence>(3), camera).has_value());
}

}  // namespace
}  // namespace slicecap::capture
