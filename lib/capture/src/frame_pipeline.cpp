// The per-frame pipeline: detect, pose, gate, measure the window against the white references.
#include "slicecap/capture/frame_pipeline.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "frame_checks.hpp"
#include "slicecap/capture/area_reading.hpp"
#include "slicecap/capture/light_model.hpp"
#include "slicecap/capture/linear_view.hpp"
#include "slicecap/capture/marker_search.hpp"
#include "slicecap/capture/planar_pose.hpp"
#include "slicecap/core/angles.hpp"
#include "slicecap/vision/tag_family.hpp"

namespace slicecap::capture {
namespace {

using namespace frame_checks;

// Rows around the window and the references that still count: the hand moves between the latest
// pose and this frame (a tenth of the frame's height covers a 48-frame simulated sweep's step),
// and blur spreads a row's light to its neighbours.
constexpr double kRowMarginFraction = 0.1;
constexpr double kBlurRowMarginPx = 8.0;

}  // namespace

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
  // An LED-off frame and, when located, its own pose: the camera moved between it and the LED-on
  // frame, so the same target points sit at other pixels.
  struct Ambient {
    hal::Frame frame;
    std::optional<vision::Pose> pose;
  };
  std::optional<Ambient> ambient;      // the latest LED-off frame
  std::optional<Ambient> nextAmbient;  // offline: the LED-off frame after the coming LED-on ones
  std::uint64_t frameIndex = 0;

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
  Ambient makeAmbient(const hal::Frame& frame, bool inTurn) {
    Ambient a{frame, std::nullopt};
    const bool acquiring = inTurn && !search.tracking();
    if (!settings.poseAmbientFrames && !acquiring) return a;
    std::vector<PlaneCorrespondence> corners;
    for (const auto& marker : search.search(frame, false).markers)
      if (const vision::Marker* geometry = target.findMarker(marker.id))
        for (int c = 0; c < 4; ++c)
          corners.push_back(
              {{geometry->cornersMm[c].xMm, geometry->cornersMm[c].yMm}, marker.cornersPx[c]});
    if (static_cast<int>(corners.size()) < 4 * settings.minMarkers) return a;
    const auto estimate = estimatePlanarPose(corners, camera);
    if (!estimate || estimate->residualRmsPx > settings.maxPoseResidualPx) return a;
    if (acquiring) search.located(estimate->pose);
    if (settings.poseAmbientFrames) a.pose = estimate->pose;
    return a;
  }

  // The room light's radiance over a target area for an LED-on frame at `pose`, from its
  // ambient terms (zero for none), and its variance: each LED-off frame read at its own pose
  // when located, else at the LED-on frame's pixels.
  AreaReading ambientAt(const std::vector<AmbientTerm>& terms, AreaSpec area,
                        const vision::Pose& pose) const {
    area.clipFraction = 2.0;
    AreaReading sum;
    for (const AmbientTerm& term : terms) {
      AreaReading value;
      if (term.pose)
        value = readArea(*term.frame, *term.pose, camera, area, settings.noise, *codes);
      if (!value.inside) value = readArea(*term.frame, pose, camera, area, settings.noise, *codes);
      sum.mean += term.weight * value.mean;
      sum.variance += term.weight * term.weight * value.variance;
    }
    return sum;
  }

  // The window's pixels in an LED-on frame at `pose`, or why they give no sample.
  std::optional<GateFailure> readWindow(const hal::Frame& frame, const vision::Pose& pose,
                                        AreaReading* window) const {
    AreaSpec spec = windowArea;
    spec.clipFraction = settings.clipFraction;
    *window = readArea(frame, pose, camera, spec, settings.noise, *codes);
    if (!window->inside)
      return GateFailure{RejectReason::WindowOccluded, "window out of the image"};
    if (window->clipped && !settings.hdr)
      return GateFailure{RejectReason::WindowClipped, "window saturated"};
    return std::nullopt;
  }

  // The window's radiance (its reading minus the room light) and the white references' (room
  // light subtracted, with their noise) of an LED-on frame at `pose`, or why it gives none.
  std::optional<GateFailure> readReferences(const hal::Frame& frame, const vision::Pose& pose,
                                            const std::vector<AmbientTerm>& roomLight,
                                            const AreaReading& window, Rgb* windowRadiance,
                                            std::vector<ReferenceObservation>* observations,
                                            std::vector<ReferenceObservation>* unlit) const {
    *windowRadiance = window.mean - ambientAt(roomLight, windowArea, pose).mean;
    for (const auto& reference : references) {
      AreaSpec spec = reference.area;
      spec.clipFraction = settings.clipFraction;
      const AreaReading area = readArea(frame, pose, camera, spec, settings.noise, *codes);
      if (!area.inside) continue;
      if (area.clipped)
        return GateFailure{RejectReason::WindowClipped, "white reference saturated"};
      const AreaReading room = ambientAt(roomLight, reference.area, pose);
      const Rgb value = area.mean - room.mean;
      Rgb sigma;
      for (int c = 0; c < 3; ++c)
        sigma[c] = std::sqrt(area.variance[c] + room.variance[c]);
      const ReferenceObservation observation{
          {reference.centre.x(), reference.centre.y(), 0.0}, value, reference.albedo, sigma};
      // No LED light (the arm covers it, or noise in a dark frame): not for the fit, but checked
      // against the fitted light (fitLight).
      (value.minChannel() > 0 ? observations : unlit)->push_back(observation);
    }
    if (observations->size() < 5)
      return GateFailure{RejectReason::WindowOccluded, "white references out of the image"};
    return std::nullopt;
  }

  // The point light fitted to the references, or a rejection when they disagree by more than
  // noise explains plus the margin for an occluder (maxReferenceResidual), or one that reads no
  // LED light (`unlit`) falls short of the fitted light by as much.
  std::optional<GateFailure> fitLight(const std::vector<ReferenceObservation>& observations,
                                      const std::vector<ReferenceObservation>& unlit,
                                      const Direction& nominalLight, LightFit* fit,
                                      double* limit) const {
    LightFitParams fitParams;
    const UnitVector toLight = toUnitVector(nominalLight);
    fitParams.initialPositionMm = {toLight.x * settings.nominalLightDistanceMm,
                                   toLight.y * settings.nominalLightDistanceMm,
                                   toLight.z * settings.nominalLightDistanceMm};
    try {
      *fit = fitPointLight(observations, fitParams);
    } catch (const std::invalid_argument& error) {
      return GateFailure{RejectReason::WindowOccluded, error.what()};
    }
    if (!fit->converged)
      return GateFailure{RejectReason::WindowOccluded, "light fit: " + fit->message};
    *limit = settings.maxReferenceResidual + noiseAllowance(*fit, settings.referenceNoiseSigmas);
    if (fit->weightedResidualRms > *limit)
      return GateFailure{RejectReason::WindowOccluded,
                         "white references disagree by " +
                             std::to_string(fit->weightedResidualRms) +
                             ", noise and margin allow " + std::to_string(*limit)};
    for (const ReferenceObservation& o : unlit) {
      const Rgb irradiance = fit->light.irradianceAt(o.point);
      for (int c = 0; c < 3; ++c) {
        const double expected = o.albedo[c] / std::numbers::pi * irradiance[c];
        if (expected - o.radiance[c] >
            settings.referenceNoiseSigmas * o.sigma[c] + settings.maxReferenceResidual * expected)
          return GateFailure{RejectReason::WindowOccluded,
                             "a white reference (at " + std::to_string(o.point.x) + ", " +
                                 std::to_string(o.point.y) + " mm) gets no LED light, " +
                                 std::to_string(expected / o.sigma[c]) + " sigma expected"};
      }
    }
    return std::nullopt;
  }

  // The window's sample square in cells (HDR sweeps): each cell's radiance per unit exposure x
  // gain minus the room light (LED-off frames of the same level), its variance, its level as
  // exposed and whether it clipped; a cell out of the image counts as clipped (unusable).
  std::vector<HdrCell> readCells(const hal::Frame& frame, const vision::Pose& pose,
                                 const std::vector<AmbientTerm>& roomLight) const {
    const vision::RectMm& r = windowArea.rectMm;
    const int n = kHdrCellsPerSide;
    const double scale =
        exposureKnown(frame) ? frame.metadata.exposureUs * frame.metadata.gain : 1.0;
    std::vector<HdrCell> cells;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x0 = r.xMinMm + i * r.widthMm() / n, y0 = r.yMinMm + j * r.heightMm() / n;
        const AreaSpec spec{
            {x0, y0, x0 + r.widthMm() / n, y0 + r.heightMm() / n}, 0.0, settings.clipFraction};
        const AreaReading area = readArea(frame, pose, camera, spec, settings.noise, *codes);
        const AreaReading room = ambientAt(roomLight, spec, pose);
        HdrCell cell;
        cell.radiance = area.mean - room.mean;
        for (int c = 0; c < 3; ++c)
          cell.variance[c] = area.variance[c] + room.variance[c];
        cell.level = area.mean.maxChannel() * scale;
        cell.clipped = area.clipped || !area.inside;
        cells.push_back(cell);
      }
    return cells;
  }

  // The LED-off frames on both sides of `timeUs`, weighted linearly in time, when the following
  // one is known (offline), else the one there is.
  std::vector<AmbientTerm> ambientTerms(std::int64_t timeUs) const {
    const auto term = [](const Ambient& a, double weight) {
      return AmbientTerm{&a.frame, a.pose, weight};
    };
    if (!ambient && !nextAmbient) return {};
    if (!ambient) return {term(*nextAmbient, 1.0)};
    const bool after = nextAmbient && nextAmbient->frame.metadata.timestampUs > timeUs;
    if (!after) return {term(*ambient, 1.0)};
    const double t0 = static_cast<double>(ambient->frame.metadata.timestampUs);
    const double t1 = static_cast<double>(nextAmbient->frame.metadata.timestampUs);
    const double w = std::clamp((static_cast<double>(timeUs) - t0) / (t1 - t0), 0.0, 1.0);
    return {term(*ambient, 1.0 - w), term(*nextAmbient, w)};
  }
};

FramePipeline::FramePipeline(vision::TargetGeometry target, vision::CameraModel camera,
                             PipelineSettings settings)
    : state_(std::make_unique<State>(std::move(target), std::move(camera), settings)) {
  std::string error;
  if (!state_->camera.isValid(&error))
    throw std::invalid_argument("capture pipeline: camera: " + error);
  if (const auto problem = vision::findTargetProblem(state_->target))
    throw std::invalid_argument("capture pipeline: target: " + *problem);
  if (!settings.noise.isValid(&error)) throw std::invalid_argument("capture pipeline: " + error);
  const vision::RectMm& w = state_->target.window;
  const double half = settings.windowSampleFraction * std::min(w.widthMm(), w.heightMm()) / 2.0;
  const vision::PointMm c = w.centre();
  state_->windowArea.rectMm = {c.xMm - half, c.yMm - half, c.xMm + half, c.yMm + half};
  // Each white patch gives up to 4 observations (its quarters); the pixels near a quarter's
  // outline are left out (referenceInsetPx) so blur or a slightly wrong pose does not mix in the
  // window or a marker.
  for (const auto& patch : state_->target.patches) {
    if (patch.kind != vision::PatchKind::White) continue;
    const vision::RectMm& r = patch.rect;
    const int nx = r.widthMm() > 2 * r.heightMm() ? 4 : (r.widthMm() * 2 < r.heightMm() ? 1 : 2);
    const int ny = r.heightMm() > 2 * r.widthMm() ? 4 : (r.heightMm() * 2 < r.widthMm() ? 1 : 2);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x0 = r.xMinMm + i * r.widthMm() / nx, x1 = x0 + r.widthMm() / nx;
        const double y0 = r.yMinMm + j * r.heightMm() / ny, y1 = y0 + r.heightMm() / ny;
        const vision::RectMm part{x0, y0, x1, y1};
        state_->references.push_back({AreaSpec{part, settings.referenceInsetPx},
                                      {part.centre().xMm, part.centre().yMm},
                                      patch.albedo});
      }
  }
  if (state_->references.size() < 5)
    throw std::invalid_argument("capture pipeline: target: fewer than 5 white reference areas");
}

FramePipeline::~FramePipeline() = default;
FramePipeline::FramePipeline(FramePipeline&&) noexcept = default;
FramePipeline& FramePipeline::operator=(FramePipeline&&) noexcept = default;

// A frame process() rejects as "bad_frame" is not read as room light either: its pixels are not
// where the LED-on frame's are, or not in its encoding.
void FramePipeline::setAmbientFrame(const hal::Frame& frame) {
  if (badFrameDetail(frame, state_->camera.intrinsics) || !offOverSampleRows(frame)) return;
  state_->ambient = state_->makeAmbient(frame, false);
}

void FramePipeline::setFollowingAmbientFrame(const hal::Frame& frame) {
  State& s = *state_;
  if (badFrameDetail(frame, s.camera.intrinsics) || !offOverSampleRows(frame)) return;
  if (s.nextAmbient && s.nextAmbient->frame.metadata.timestampUs == frame.metadata.timestampUs)
    return;
  s.nextAmbient = s.makeAmbient(frame, false);
}

// An LED-off frame offered as room light (offline) is one only if the LED was off over the rows
// a sample reads, as process() judges it.
bool FramePipeline::offOverSampleRows(const hal::Frame& frame) const {
  const int height = frame.image.height;
  const RowSpan rows = state_->predictedRowsOfInterest(height).value_or(RowSpan{0, height - 1});
  return ledStateOver(frame, rows) == hal::LedExposure::State::Off;
}

std::vector<AmbientTerm> FramePipeline::ambientTermsFor(std::int64_t timeUs) const {
  return state_->ambientTerms(timeUs);
}

FrameOutcome FramePipeline::process(const hal::Frame& frame, const SliceId& slice) {
  State& s = *state_;
  const std::uint64_t index = s.frameIndex++;
  if (auto detail = badFrameDetail(frame, s.camera.intrinsics))
    return rejected(RejectReason::BadFrame, std::move(*detail));
  // The LED's state over the rows a sample reads, predicted from the latest pose: a frame the LED
  // switched during is neither a sample nor room light. Without a pose yet, a frame mixed over
  // all its rows may still be clean where the target is: it is located, and its own rows decide.
  const int height = frame.image.height;
  const std::optional<RowSpan> predictedRows = s.predictedRowsOfInterest(height);
  const hal::LedExposure::State ledState =
      ledStateOver(frame, predictedRows.value_or(RowSpan{0, height - 1}));
  if (ledState == hal::LedExposure::State::Mixed && predictedRows)
    return rejected(RejectReason::LedTransition, ledTransitionDetail(*predictedRows));
  if (ledState == hal::LedExposure::State::Off) {
    if (s.nextAmbient && s.nextAmbient->frame.metadata.timestampUs == frame.metadata.timestampUs) {
      s.ambient = std::move(s.nextAmbient);  // already located by setFollowingAmbientFrame
      s.nextAmbient.reset();
    } else {
      s.ambient = s.makeAmbient(frame, true);
    }
    FrameOutcome outcome;
    outcome.kind = FrameOutcome::Kind::Ambient;
    return outcome;
  }
  FrameOutcome outcome;
  auto& m = outcome.measurement;
  // Markers within the frame's detection budget (MarkerSearch: tracked from the latest pose, a
  // lost target re-acquired over several frames), so no frame stalls the camera.
  MarkerSearchResult found = s.search.search(frame);
  m.trackedScale = found.trackedScale;
  m.detectionPasses = found.passes;
  m.detectionWorkPx = found.workPx;
  const std::vector<DetectedMarker> markers = std::move(found.markers);
  std::vector<PlaneCorrespondence> corners;
  std::vector<const DetectedMarker*> known;
  for (const auto& marker : markers) {
    const vision::Marker* geometry = s.target.findMarker(marker.id);
    if (!geometry) continue;
    known.push_back(&marker);
    for (int c = 0; c < 4; ++c)
      corners.push_back(
          {{geometry->cornersMm[c].xMm, geometry->cornersMm[c].yMm}, marker.cornersPx[c]});
  }
  m.markerCount = static_cast<int>(known.size());
  const std::string markerText =
      std::to_string(known.size()) + " of " + std::to_string(s.target.markers.size()) + " markers";
  if (m.markerCount < s.settings.minMarkers && found.deferred)
    return rejected(RejectReason::DetectionDeferred,
                    markerText + " in this frame's detection budget", outcome);
  if (m.markerCount < s.settings.minMarkers)
    return rejected(RejectReason::TooFewMarkers, markerText, outcome);
  const auto estimate = estimatePlanarPose(corners, s.camera);
  if (!estimate) return rejected(RejectReason::TooFewMarkers, markerText + ", no pose", outcome);
  const vision::Pose& pose = estimate->pose;
  m.pose = pose;
  if (estimate->residualRmsPx <= s.settings.maxPoseResidualPx) s.search.located(pose);
  m.rowsOfInterest = rowsOfInterest(s.target, s.camera, pose, height, kBlurRowMarginPx);
  if (ledStateOver(frame, *m.rowsOfInterest) != hal::LedExposure::State::On)
    return rejected(RejectReason::LedTransition, ledTransitionDetail(*m.rowsOfInterest), outcome);
  const Eigen::Vector3d cameraCentre = pose.cameraCentreMm();
  m.poseResidualPx = estimate->residualRmsPx;
  m.cameraDistanceMm = cameraCentre.norm();
  if (cameraCentre.z() <= 0)
    return rejected(RejectReason::PoseResidual, "camera below the target", outcome);
  m.view = vision::directionFrom(Eigen::Vector3d::Zero(), cameraCentre);
  outcome.viewElevationErrorDeg = m.view->thetaDeg - slice.elevations.thetaVDeg;
  const double phiLight = slice.kind == SliceKind::Axial
                              ? wrapDeg360(m.view->phiDeg - kAxialOffsetDeg)
                              : wrapDeg360(360.0 - m.view->phiDeg);
  m.nominalLight = Direction{static_cast<double>(slice.elevations.thetaIDeg), phiLight};
  if (m.poseResidualPx > s.settings.maxPoseResidualPx)
    return rejected(RejectReason::PoseResidual, std::to_string(m.poseResidualPx) + " px", outcome);
  if (std::abs(*outcome.viewElevationErrorDeg) > s.settings.elevationToleranceDeg)
    return rejected(RejectReason::ElevationOff,
                    "view elevation " + std::to_string(m.view->thetaDeg) + " deg", outcome);
  m.sharpness = blurSharpness(LinearView(frame, *s.codes), known);
  if (m.sharpness < s.settings.minSharpness)
    return rejected(RejectReason::Blurred, "edge sharpness " + std::to_string(m.sharpness),
                    outcome);

  AreaReading window;
  if (auto failure = s.readWindow(frame, pose, &window))
    return rejected(failure->reason, std::move(failure->detail), outcome);
  // The same room-light term for the window and every reference, found once.
  // Without the LED alternating, an LED-off frame is a stray (a sweep's first): it would stand
  // for the room light of the whole sweep, read at pixels the camera has long moved from.
  const std::vector<AmbientTerm> ambient = s.settings.requireAmbient
                                               ? s.ambientTerms(frame.metadata.timestampUs)
                                               : std::vector<AmbientTerm>{};
  if (s.settings.requireAmbient && ambient.empty())
    return rejected(RejectReason::NoAmbientFrame, "no LED-off frame yet", outcome);
  // Each frame is read per unit of exposure x gain; a frame whose camera reported none is read as
  // it is, which matches another such frame only (the same locked exposure assumed).
  for (const AmbientTerm& term : ambient)
    if (exposureKnown(*term.frame) != exposureKnown(frame))
      return rejected(RejectReason::NoAmbientFrame,
                      exposureKnown(frame)
                          ? "the LED-off frame's exposure is unknown"
                          : "this frame's exposure is unknown, the LED-off frame's is not",
                      outcome);
  Rgb windowRadiance;
  std::vector<ReferenceObservation> observations, unlit;
  LightFit fit;
  auto failure =
      s.readReferences(frame, pose, ambient, window, &windowRadiance, &observations, &unlit);
  double limit = 0.0;
  if (!failure) failure = s.fitLight(observations, unlit, *m.nominalLight, &fit, &limit);
  if (fit.converged) m.referenceDisagreement = fit.weightedResidualRms;
  if (fit.converged) m.referenceDisagreementLimit = limit;
  if (failure) return rejected(failure->reason, std::move(failure->detail), outcome);
  m.fittedLight = fit.light;
  m.measuredLight = fit.light.directionFrom({0.0, 0.0, 0.0});
  m.measuredLightSigmaDeg = fit.directionSigmaDeg;
  const Rgb irradiance = fit.light.irradianceAt({0.0, 0.0, 0.0});
  FrameSample sample;
  sample.timestampUs = frame.metadata.timestampUs;
  sample.frameIndex = index;
  sample.view = *m.view;
  sample.light = m.measuredLightSigmaDeg < s.settings.measuredLightMaxSigmaDeg ? *m.measuredLight
                                                                               : *m.nominalLight;
  for (int c = 0; c < 3; ++c)
    sample.value[c] = irradiance[c] > 0 ? std::max(0.0, windowRadiance[c]) / irradiance[c] : 0.0;
  if (s.settings.hdr) {
    // The references' SNR^2 stands for the irradiance's inverse relative variance: a short
    // exposure's dark references give a noisier fit, and weigh less in the bin's irradiance.
    HdrReading hdr;
    hdr.cells = s.readCells(frame, pose, ambient);
    hdr.irradiance = irradiance;
    for (const ReferenceObservation& o : observations)
      for (int c = 0; c < 3; ++c)
        if (o.sigma[c] > 0) hdr.irradianceWeight += std::pow(o.radiance[c] / o.sigma[c], 2);
    sample.hdr = std::move(hdr);
  }
  outcome.kind = FrameOutcome::Kind::Sample;
  outcome.sample = sample;
  outcome.detail = markerText;
  return outcome;
}

}  // namespace slicecap::capture
