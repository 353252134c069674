// The frame pipeline's stages: screen (unreadable, LED switching, room-light frames), locate
// (markers and pose), check the view (geometry and blur), measure (window against references).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "frame_pipeline_state.hpp"
#include "slicecap/core/angles.hpp"

namespace slicecap::capture {

using namespace frame_checks;

// Stage 1: a frame that cannot be read, one the LED switched during, or an LED-off frame (kept as
// room light) ends here. The LED's state over the rows a sample reads is predicted from the latest
// pose: a frame the LED switched during is neither a sample nor room light. Without a pose yet, a
// frame mixed over all its rows may still be clean where the target is: it is located, and its
// own rows decide.
std::optional<FrameOutcome> FramePipeline::State::screen(const hal::Frame& frame) {
  if (auto detail = badFrameDetail(frame, camera.intrinsics))
    return rejected(RejectReason::BadFrame, std::move(*detail));
  const int height = frame.image.height;
  const std::optional<RowSpan> predictedRows = predictedRowsOfInterest(height);
  const hal::LedExposure::State ledState =
      ledStateOver(frame, predictedRows.value_or(RowSpan{0, height - 1}));
  if (ledState == hal::LedExposure::State::Mixed && predictedRows)
    return rejected(RejectReason::LedTransition, ledTransitionDetail(*predictedRows));
  if (ledState != hal::LedExposure::State::Off) return std::nullopt;
  std::optional<Ambient> previous = std::move(ambient);
  if (nextAmbient && nextAmbient->frame.metadata.timestampUs == frame.metadata.timestampUs) {
    ambient = std::move(nextAmbient);  // already located by setFollowingAmbientFrame
    nextAmbient.reset();
  } else {
    ambient = makeAmbient(frame, true);
  }
  if (const std::optional<RowSpan> lit = litOwnRows(*ambient)) {
    ambient = std::move(previous);
    return rejected(RejectReason::LedTransition, ledTransitionDetail(*lit));
  }
  FrameOutcome outcome;
  outcome.kind = FrameOutcome::Kind::Ambient;
  outcome.measurement.pose = ambient->pose;  // offline: another level may borrow it
  // Consecutive LED-off frames: how much the room light moved in one frame period.
  if (previous && frame.metadata.sequence == previous->frame.metadata.sequence + 1)
    outcome.measurement.roomChange = roomChangeBetween(*previous, *ambient);
  return outcome;
}

// Stage 2: the markers within the frame's detection budget (MarkerSearch: tracked from the latest
// pose, a lost target re-acquired over several frames, so no frame stalls the camera), the pose,
// and the LED on over the rows the pose puts the window and references in.
std::optional<FrameOutcome> FramePipeline::State::locate(const hal::Frame& frame,
                                                         FrameOutcome& outcome, Located& located) {
  auto& m = outcome.measurement;
  MarkerSearchResult found = search.search(frame);
  m.trackedScale = found.trackedScale;
  m.detectionPasses = found.passes;
  m.detectionWorkPx = found.workPx;
  located.markers = std::move(found.markers);
  std::vector<PlaneCorrespondence> corners;
  for (const auto& marker : located.markers) {
    const vision::Marker* geometry = target.findMarker(marker.id);
    if (!geometry) continue;
    located.known.push_back(&marker);
    for (int c = 0; c < 4; ++c)
      corners.push_back(
          {{geometry->cornersMm[c].xMm, geometry->cornersMm[c].yMm}, marker.cornersPx[c]});
  }
  m.markerCount = static_cast<int>(located.known.size());
  located.markerText = std::to_string(located.known.size()) + " of " +
                       std::to_string(target.markers.size()) + " markers";
  if (m.markerCount < settings.minMarkers && found.deferred)
    return rejected(RejectReason::DetectionDeferred,
                    located.markerText + " in this frame's detection budget", outcome);
  if (m.markerCount < settings.minMarkers)
    return rejected(RejectReason::TooFewMarkers, located.markerText, outcome);
  const auto estimate = estimatePlanarPose(corners, camera);
  if (!estimate)
    return rejected(RejectReason::TooFewMarkers, located.markerText + ", no pose", outcome);
  located.pose = estimate->pose;
  m.pose = located.pose;
  if (estimate->residualRmsPx <= settings.maxPoseResidualPx)
    locatedAt(located.pose, frame.metadata.timestampUs);
  m.rowsOfInterest =
      rowsOfInterest(target, camera, located.pose, frame.image.height, kBlurRowMarginPx);
  if (ledStateOver(frame, *m.rowsOfInterest) != hal::LedExposure::State::On)
    return rejected(RejectReason::LedTransition, ledTransitionDetail(*m.rowsOfInterest), outcome);
  m.poseResidualPx = estimate->residualRmsPx;
  return std::nullopt;
}

// Stage 3: the view (and the nominal light) from the pose, and the gates on the geometry and the
// image: a camera below the target, a poor pose, the view elevation off the slice's, blur.
std::optional<FrameOutcome> FramePipeline::State::checkView(const hal::Frame& frame,
                                                            const SliceId& slice,
                                                            FrameOutcome& outcome,
                                                            const Located& located) const {
  auto& m = outcome.measurement;
  const Eigen::Vector3d cameraCentre = located.pose.cameraCentreMm();
  m.cameraDistanceMm = cameraCentre.norm();
  if (cameraCentre.z() <= 0)
    return rejected(RejectReason::PoseResidual, "camera below the target", outcome);
  m.view = vision::directionFrom(Eigen::Vector3d::Zero(), cameraCentre);
  outcome.viewElevationErrorDeg = m.view->thetaDeg - slice.elevations.thetaVDeg;
  const double phiLight = slice.kind == SliceKind::Axial
                              ? wrapDeg360(m.view->phiDeg - kAxialOffsetDeg)
                              : wrapDeg360(360.0 - m.view->phiDeg);
  m.nominalLight = Direction{static_cast<double>(slice.elevations.thetaIDeg), phiLight};
  if (m.poseResidualPx > settings.maxPoseResidualPx)
    return rejected(RejectReason::PoseResidual, std::to_string(m.poseResidualPx) + " px", outcome);
  if (std::abs(*outcome.viewElevationErrorDeg) > settings.elevationToleranceDeg)
    return rejected(RejectReason::ElevationOff,
                    "view elevation " + std::to_string(m.view->thetaDeg) + " deg", outcome);
  m.sharpness = blurSharpness(LinearView(frame, *codes), located.known);
  if (m.sharpness < settings.minSharpness)
    return rejected(RejectReason::Blurred, "edge sharpness " + std::to_string(m.sharpness),
                    outcome);
  return std::nullopt;
}

// The room-light terms of an LED-on frame, or why it cannot have them. Without the LED
// alternating, an LED-off frame is a stray (a sweep's first): it would stand for the room light of
// the whole sweep, read at pixels the camera has long moved from. Each frame is read per unit of
// exposure x gain; a frame whose camera reported none is read as it is, which matches another such
// frame only (the same locked exposure assumed).
std::optional<GateFailure> FramePipeline::State::roomLightFor(
    const hal::Frame& frame, const vision::Pose& pose, std::vector<AmbientTerm>& terms) const {
  if (!settings.requireAmbient) return std::nullopt;
  terms = ambientTerms(frame.metadata.timestampUs, pose);
  if (terms.empty()) return GateFailure{RejectReason::NoAmbientFrame, "no LED-off frame yet"};
  for (const AmbientTerm& term : terms)
    if (exposureKnown(*term.frame) != exposureKnown(frame))
      return GateFailure{RejectReason::NoAmbientFrame,
                         exposureKnown(frame)
                             ? "the LED-off frame's exposure is unknown"
                             : "this frame's exposure is unknown, the LED-off frame's is not"};
  return std::nullopt;
}

// An LED-on frame between two LED-off frames (`terms`) whose room light on the window changes
// between them by more than their noise and by more than maxRoomLightChange of the window's LED
// light (RGB vectors), when the nearer was taken further than maxRoomLightDistanceMm from it:
// what the room gave at its own place is known from neither, and can be off by about that
// change. Where the room light does not change (a dark or evenly lit room) the frames' places do
// not matter, so dropped frames cost no sample there. An LED-off frame the live loop's detection
// budget left unlocated is not judged: its place is unknown, not far.
std::optional<GateFailure> FramePipeline::State::roomLightUnseen(
    const std::vector<AmbientTerm>& terms, const vision::Pose& pose, const RoomLightSpan& span,
    const Rgb& windowReading) const {
  const double limitMm = settings.maxRoomLightDistanceMm.value_or(0.0);
  if (!(limitMm > 0.0) || terms.size() != 2) return std::nullopt;
  if (!span.nearestMm || *span.nearestMm <= limitMm) return std::nullopt;
  const AreaReading a = ambientAt({{terms[0].frame, terms[0].pose, 1.0}}, windowArea, pose);
  const AreaReading b = ambientAt({{terms[1].frame, terms[1].pose, 1.0}}, windowArea, pose);
  double sigmas = 0.0, change2 = 0.0, led2 = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double change = a.mean[c] - b.mean[c];
    const double sigma = std::sqrt(a.variance[c] + b.variance[c]);
    if (sigma > 0.0) sigmas = std::max(sigmas, std::abs(change) / sigma);
    const double led = std::max(0.0, windowReading[c] - 0.5 * (a.mean[c] + b.mean[c]));
    change2 += change * change;
    led2 += led * led;
  }
  const double toLed = led2 > 0.0 ? std::sqrt(change2 / led2) : 0.0;
  if (!(sigmas > settings.referenceNoiseSigmas) || !(toLed > settings.maxRoomLightChange))
    return std::nullopt;
  char detail[200];
  std::snprintf(detail, sizeof detail,
                "the nearer LED-off frame was %.1f mm away (limit %.0f) and the room light on the "
                "window changed by %.1f %% of the LED's between the two (%.1f sigma)",
                *span.nearestMm, limitMm, 100.0 * toLed, sigmas);
  return GateFailure{RejectReason::RoomLightUnseen, detail};
}

// The black patch's LED light against what the fitted light and its albedo say it should be:
// pi L / (E albedo), the channels' mean. Only a sample frame's: the light fit holds.
std::optional<double> FramePipeline::State::blackReadingOf(const hal::Frame& frame,
                                                           const vision::Pose& pose,
                                                           const std::vector<AmbientTerm>& roomLight,
                                                           const PointLight& light) const {
  if (!black) return std::nullopt;
  const AreaReading area = readArea(frame, pose, camera, black->area, settings.noise, *codes);
  if (!area.inside) return std::nullopt;
  const Rgb radiance = area.mean - ambientAt(roomLight, black->area, pose).mean;
  const Rgb irradiance = light.irradianceAt({black->centre.x(), black->centre.y(), 0.0});
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    if (!(irradiance[c] > 0.0) || !(black->albedo[c] > 0.0)) return std::nullopt;
    sum += std::numbers::pi * radiance[c] / (irradiance[c] * black->albedo[c]);
  }
  return sum / 3.0;
}

// Stage 4: the window against the white references: the window's reading, the room light, the
// light fitted to the references (the occlusion gate), the sample, and for HDR sweeps its cells.
std::optional<FrameOutcome> FramePipeline::State::measure(const hal::Frame& frame,
                                                          FrameOutcome& outcome,
                                                          const Located& located,
                                                          FrameSample& sample) {
  auto& m = outcome.measurement;
  AreaReading window;
  if (auto failure = readWindow(frame, located.pose, &window))
    return rejected(failure->reason, std::move(failure->detail), outcome);
  // The same room-light term for the window and every reference, found once.
  std::vector<AmbientTerm> roomLight;
  if (auto failure = roomLightFor(frame, located.pose, roomLight))
    return rejected(failure->reason, std::move(failure->detail), outcome);
  if (roomLight.size() == 2) {
    const RoomLightSpan span = roomLightSpan(roomLight[0].pose, roomLight[1].pose, located.pose);
    m.roomLightApartMm = span.apartMm;
    m.roomLightNearestMm = span.nearestMm;
    m.roomLightSequenceApart =
        static_cast<std::int64_t>(roomLight[1].frame->metadata.sequence) -
        static_cast<std::int64_t>(roomLight[0].frame->metadata.sequence);
    if (auto failure = roomLightUnseen(roomLight, located.pose, span, window.mean))
      return rejected(failure->reason, std::move(failure->detail), outcome);
  }
  Rgb windowRadiance;
  std::vector<ReferenceObservation> observations, unlit;
  LightFit fit;
  RoomShare share;
  auto failure = readReferences(frame, located.pose, roomLight, window, &windowRadiance,
                                &observations, &unlit, &share);
  if (!roomLight.empty() && share.led > 0.0) m.roomToLed = share.room / share.led;
  double limit = 0.0;
  if (!failure) failure = fitLight(observations, unlit, *m.nominalLight, &fit, &limit);
  if (fit.converged) m.referenceDisagreement = fit.weightedResidualRms;
  if (fit.converged) m.referenceDisagreementLimit = limit;
  if (failure) return rejected(failure->reason, std::move(failure->detail), outcome);
  m.fittedLight = fit.light;
  m.measuredLight = fit.light.directionFrom({0.0, 0.0, 0.0});
  m.measuredLightSigmaDeg = fit.directionSigmaDeg;
  const Rgb irradiance = fit.light.irradianceAt({0.0, 0.0, 0.0});
  sample.timestampUs = frame.metadata.timestampUs;
  sample.view = *m.view;
  sample.light = m.measuredLightSigmaDeg < settings.measuredLightMaxSigmaDeg ? *m.measuredLight
                                                                             : *m.nominalLight;
  Rgb windowLight;
  for (int c = 0; c < 3; ++c)
    windowLight[c] = irradiance[c] > 0 ? windowRadiance[c] / irradiance[c] : 0.0;
  for (int c = 0; c < 3; ++c) sample.value[c] = std::max(0.0, windowLight[c]);
  m.windowLight = windowLight;
  sample.cells = readWindowCells(frame, located.pose, roomLight, fit.light, sample.light);
  m.blackReading = blackReadingOf(frame, located.pose, roomLight, fit.light);
  if (frame.encoding == PixelEncoding::Srgb8) m.windowAtBlack = window.atBlack;
  if (settings.hdr) {
    // The references' SNR^2 stands for the irradiance's inverse relative variance: a short
    // exposure's dark references give a noisier fit, and weigh less in the bin's irradiance.
    HdrReading hdr;
    hdr.cells = readCells(frame, located.pose, roomLight);
    hdr.irradiance = irradiance;
    for (const ReferenceObservation& o : observations)
      for (int c = 0; c < 3; ++c)
        if (o.sigma[c] > 0) hdr.irradianceWeight += std::pow(o.radiance[c] / o.sigma[c], 2);
    sample.hdr = std::move(hdr);
  }
  return std::nullopt;
}

}  // namespace slicecap::capture
