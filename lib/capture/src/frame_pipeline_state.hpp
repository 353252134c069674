// The frame pipeline's state and its stages (frame_pipeline.cpp runs them; frame_stages.cpp holds
// the stages): the target, camera and settings, the marker search, the room-light frames.
#pragma once

#include <algorithm>
#include <cmath>
#include <iterator>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "frame_checks.hpp"
#include "slicecap/capture/area_reading.hpp"
#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/capture/light_model.hpp"
#include "slicecap/capture/linear_view.hpp"
#include "slicecap/capture/marker_search.hpp"
#include "slicecap/capture/planar_pose.hpp"
#include "room_light_weight.hpp"

namespace slicecap::capture {

// Rows around the window and the references that still count: the hand moves between the latest
// pose and this frame (a tenth of the frame's height covers a 48-frame simulated sweep's step),
// and blur spreads a row's light to its neighbours.
inline constexpr double kRowMarginFraction = 0.1;
inline constexpr double kBlurRowMarginPx = 8.0;

// The markers found and the pose they give (FramePipeline::State::locate).
struct FramePipeline::Located {
  std::vector<DetectedMarker> markers;
  std::vector<const DetectedMarker*> known;  // into `markers`: those of the target
  std::string markerText;                    // "12 of 16 markers"
  vision::Pose pose;
};

struct FramePipeline::State {
  vision::TargetGeometry target;
  vision::CameraModel camera;
  PipelineSettings settings;
  // settings.toneCurve's table, or sRGB's: how every 8-bit frame is read.
  std::shared_ptr<const CodeTable> codes;
  MarkerSearch search;
  AreaSpec windowArea;  // the centre of the window, every pixel
  struct Reference {
    AreaSpec area;  // a part of a white patch, every pixel but near its outline
    Eigen::Vector2d centre;
    Rgb albedo;
  };
  std::vector<Reference> references;
  // The black patch (the first of the target's), read as a check on the decoding.
  std::optional<Reference> black;
  // An LED-off frame and, when located, its own pose: the camera moved between it and the LED-on
  // frame, so the same target points sit at other pixels.
  struct Ambient {
    hal::Frame frame;
    std::optional<vision::Pose> pose;
  };
  std::optional<Ambient> ambient;      // the latest LED-off frame
  std::optional<Ambient> nextAmbient;  // offline: the LED-off frame after the coming LED-on ones
  // Offline HDR: another level's located LED-off frames near the coming LED-on ones, in time order.
  std::vector<Ambient> standIns;
  std::uint64_t frameIndex = 0;
  // The time of the frame the search's latest pose was located in (this pipeline's or, through
  // FramePipeline::trackFrom, a longer level's); kept when the search drops the pose.
  std::optional<std::int64_t> lastLocatedUs;

  // `pose`, located in the frame taken at `timestampUs`, guides the next frames' search.
  void locatedAt(const vision::Pose& pose, std::int64_t timestampUs) {
    search.located(pose);
    lastLocatedUs = timestampUs;
  }

  // The rows a sample of a `heightPx`-row frame reads, predicted from the latest pose with a
  // margin for the motion since; nullopt before the target was first located.
  std::optional<RowSpan> predictedRowsOfInterest(int heightPx) const {
    if (!search.lastPose()) return std::nullopt;
    return rowsOfInterest(target, camera, *search.lastPose(), heightPx,
                          kRowMarginFraction * heightPx);
  }

  State(vision::TargetGeometry t, vision::CameraModel c, PipelineSettings s)
      : target(std::move(t)),
        camera(std::move(c)),
        settings(s),
        codes(s.toneCurve ? std::make_shared<const CodeTable>(*s.toneCurve)
                          : std::shared_ptr<const CodeTable>(&CodeTable::srgb(), [](auto*) {})),
        search(target, camera, s.detector, s.minMarkers) {}

  // An LED-off frame is located when its own pose is wanted (offline) or, in its turn in
  // process() (`inTurn`) while no pose is tracked, to re-acquire the target for the LED-on frames
  // after it (the room light shows the markers too): the search then goes on in every frame, not
  // every other one. The offline setters do not re-acquire: frames are searched in their order.
  Ambient makeAmbient(const hal::Frame& frame, bool inTurn);

  // The rows an LED-off frame located at its own pose shows the window and references in, when
  // the LED was not off over all of them: the frame would be read there as room light carrying
  // the LED's. The rows were judged from the latest pose before it was located; after dropped
  // frames (the camera moved further than kRowMarginFraction covers) they can be elsewhere.
  std::optional<RowSpan> litOwnRows(const Ambient& a) const;

  // The room light's radiance over a target area for an LED-on frame at `pose`, from its
  // ambient terms (zero for none), and its variance: each LED-off frame read at its own pose
  // when located, else at the LED-on frame's pixels.
  AreaReading ambientAt(const std::vector<AmbientTerm>& terms, AreaSpec area,
                        const vision::Pose& pose) const;

  // The window's pixels in an LED-on frame at `pose`, or why they give no sample.
  std::optional<frame_checks::GateFailure> readWindow(const hal::Frame& frame,
                                                      const vision::Pose& pose,
                                                      AreaReading* window) const;

  // The window's radiance (its reading minus the room light) and the white references' (room
  // light subtracted, with their noise) of an LED-on frame at `pose`, or why it gives none.
  // The room light's share of the references, summed over them (FrameOutcome::Measurement's
  // roomToLed).
  struct RoomShare {
    double room = 0.0, led = 0.0;
  };

  // Two located LED-off frames' room light over the white references, apart as a fraction of
  // it (FrameOutcome::Measurement::roomChange); none when either is not located or nothing of
  // the references is lit.
  std::optional<double> roomChangeBetween(const Ambient& a, const Ambient& b) const;

  std::optional<frame_checks::GateFailure> readReferences(
      const hal::Frame& frame, const vision::Pose& pose, const std::vector<AmbientTerm>& roomLight,
      const AreaReading& window, Rgb* windowRadiance,
      std::vector<ReferenceObservation>* observations,
      std::vector<ReferenceObservation>* unlit, RoomShare* share) const;

  // The point light fitted to the references, or a rejection when they disagree by more than
  // noise explains plus the margin for an occluder (maxReferenceResidual), or one that reads no
  // LED light (`unlit`) falls short of the fitted light by as much.
  std::optional<frame_checks::GateFailure> fitLight(
      const std::vector<ReferenceObservation>& observations,
      const std::vector<ReferenceObservation>& unlit, const Direction& nominalLight, LightFit* fit,
      double* limit) const;

  // The window's sample square in cells (HDR sweeps): each cell's radiance per unit exposure x
  // gain minus the room light (LED-off frames of the same level), its variance, its level as
  // exposed and whether it clipped; a cell out of the image counts as clipped (unusable).
  std::vector<HdrCell> readCells(const hal::Frame& frame, const vision::Pose& pose,
                                 const std::vector<AmbientTerm>& roomLight) const;

  // The whole window as settings.windowCellsPerSide^2 cells at their own directions
  // (window_cell_reading.cpp); nullopt without cells or when the window centre does not project.
  std::optional<WindowCells> readWindowCells(const hal::Frame& frame, const vision::Pose& pose,
                                             const std::vector<AmbientTerm>& roomLight,
                                             const PointLight& light,
                                             const Direction& sampleLight) const;

  // The stages of process(), in order; each returns the frame's outcome when the frame ends there.
  std::optional<FrameOutcome> screen(const hal::Frame& frame);
  std::optional<FrameOutcome> locate(const hal::Frame& frame, FrameOutcome& outcome,
                                     Located& located);
  std::optional<FrameOutcome> checkView(const hal::Frame& frame, const SliceId& slice,
                                        FrameOutcome& outcome, const Located& located) const;
  std::optional<frame_checks::GateFailure> roomLightFor(const hal::Frame& frame,
                                                        const vision::Pose& pose,
                                                        std::vector<AmbientTerm>& terms) const;
  std::optional<frame_checks::GateFailure> roomLightUnseen(const std::vector<AmbientTerm>& terms,
                                                           const vision::Pose& pose,
                                                           const RoomLightSpan& span,
                                                           const Rgb& windowReading) const;
  // FrameOutcome::Measurement::blackReading of an LED-on frame at `pose` (frame_stages.cpp).
  std::optional<double> blackReadingOf(const hal::Frame& frame, const vision::Pose& pose,
                                       const std::vector<AmbientTerm>& roomLight,
                                       const PointLight& light) const;
  std::optional<FrameOutcome> measure(const hal::Frame& frame, FrameOutcome& outcome,
                                      const Located& located, FrameSample& sample);

  // The LED-off frames on both sides of `timeUs`, weighted linearly where the LED-on frame was
  // taken (`pose`, when located; bracketingTerms), when the following one is known (offline),
  // else the one there is; another level's stand-ins when these are missing or not located and
  // there are any (setStandInAmbientFrames).
  std::vector<AmbientTerm> ambientTerms(std::int64_t timeUs,
                                        const std::optional<vision::Pose>& pose) const;

  // `before` and `after` (either may be missing) as the terms of a frame at `timeUs`: linear
  // between them when `after` is later, else the one there is (`before` first). The room and the
  // target stand still while the camera moves, so what an LED-off frame saw of the room light
  // (the window's reflection of a lamp above all) follows where the camera was, not when: the
  // weight is the LED-on frame's camera centre projected on the segment between theirs, when all
  // three are located and theirs are apart (room_light_weight.hpp); else linear in time. A hand
  // that pauses, jerks or whose frames were dropped moves unevenly in time, and a reflection
  // the view passes through in a few frames is then interpolated at the wrong place.
  static std::vector<AmbientTerm> bracketingTerms(const Ambient* before, const Ambient* after,
                                                  std::int64_t timeUs,
                                                  const std::optional<vision::Pose>& pose);
};

}  // namespace slicecap::capture
