// The per-frame pipeline: detect, pose, gate, measure the window against the white references.
#include "slicecap/capture/frame_pipeline.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "slicecap/capture/light_model.hpp"
#include "slicecap/capture/linear_view.hpp"
#include "slicecap/capture/marker_search.hpp"
#include "slicecap/capture/planar_pose.hpp"
#include "slicecap/core/angles.hpp"
#include "slicecap/vision/tag_family.hpp"

namespace slicecap::capture {
namespace {

// Grid points covering a rectangle of the target, about `stepMm` apart, inset by half a step.
std::vector<Eigen::Vector2d> gridPoints(const vision::RectMm& rect, int perSide) {
  std::vector<Eigen::Vector2d> points;
  for (int j = 0; j < perSide; ++j)
    for (int i = 0; i < perSide; ++i)
      points.push_back({rect.xMinMm + (i + 0.5) * rect.widthMm() / perSide,
                        rect.yMinMm + (j + 0.5) * rect.heightMm() / perSide});
  return points;
}

struct RegionMean {
  Rgb value;
  bool inside = true;
  bool clipped = false;
};

// True when the camera reported the frame's exposure and gain (else regionMean reads it unscaled).
bool exposureKnown(const hal::Frame& frame) {
  return frame.metadata.exposureUs * frame.metadata.gain > 0;
}

// Mean linear colour over target points, divided by exposure x gain (camera units per us).
RegionMean regionMean(const hal::Frame& frame, const vision::Pose& pose,
                      const vision::CameraModel& camera, const std::vector<Eigen::Vector2d>& points,
                      double clipFraction) {
  const LinearView view(frame);
  RegionMean mean;
  for (const auto& p : points) {
    const auto px = camera.project(pose.toCamera({p.x(), p.y(), 0.0}));
    if (!px || !view.inside(*px)) {
      mean.inside = false;
      return mean;
    }
    mean.value += view.at(*px, clipFraction, &mean.clipped);
  }
  const double scale = frame.metadata.exposureUs * frame.metadata.gain;
  mean.value *= 1.0 / (static_cast<double>(points.size()) * (exposureKnown(frame) ? scale : 1.0));
  return mean;
}

// Sharpness of one marker edge: the largest 1-px step of the profile across its midpoint over
// the whole step from 3 px inside to 3 px outside.
double edgeSharpness(const LinearView& view, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d mid = (a + b) / 2.0;
  Eigen::Vector2d normal(-(b - a).y(), (b - a).x());
  if (normal.norm() < 1e-9) return 0.0;
  normal.normalize();
  constexpr int kSteps = 24;  // quarter-pixel steps over [-3, 3] px
  std::vector<double> profile;
  for (int k = 0; k <= kSteps; ++k) {
    const Eigen::Vector2d p = mid + normal * (-3.0 + 6.0 * k / kSteps);
    if (!view.inside(p)) return -1.0;
    profile.push_back(view.gray(p));
  }
  const double step = std::abs(profile.back() - profile.front());
  if (step < 1e-6) return -1.0;
  double largest = 0.0;
  for (int k = 0; k + 4 <= kSteps; ++k)
    largest = std::max(largest, std::abs(profile[k + 4] - profile[k]));
  return largest / step;
}

// Why `frame` cannot be read as this camera's frame ("bad_frame"), or nullopt when it can.
std::optional<std::string> badFrameDetail(const hal::Frame& frame,
                                          const vision::CameraIntrinsics& k) {
  if (frame.image.isValid() && frame.image.width == k.widthPx && frame.image.height == k.heightPx &&
      frame.image.bitDepth == bitDepthOf(frame.encoding) &&
      (frame.image.channels == 1 || frame.image.channels == 3))
    return std::nullopt;
  return "frame " + std::to_string(frame.image.width) + " x " + std::to_string(frame.image.height) +
         " x " + std::to_string(frame.image.channels) + " at " +
         std::to_string(frame.image.bitDepth) + " bits, expected " + std::to_string(k.widthPx) +
         " x " + std::to_string(k.heightPx) + " of " + std::string(toString(frame.encoding));
}

FrameOutcome rejected(std::string reason, std::string detail, FrameOutcome outcome = {}) {
  outcome.kind = FrameOutcome::Kind::Rejected;
  outcome.sample.reset();
  outcome.rejectReason = std::move(reason);
  outcome.detail = std::move(detail);
  return outcome;
}

}  // namespace

struct FramePipeline::State {
  vision::TargetGeometry target;
  vision::CameraModel camera;
  PipelineSettings settings;
  MarkerSearch search;
  std::vector<Eigen::Vector2d> windowPoints;
  struct Reference {
    std::vector<Eigen::Vector2d> points;
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

  State(vision::TargetGeometry t, vision::CameraModel c, PipelineSettings s)
      : target(std::move(t)),
        camera(std::move(c)),
        settings(s),
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

  // The room light's radiance at target points for an LED-on frame at `pose`, from its ambient
  // terms (zero for none): each LED-off frame sampled at its own pose when located.
  Rgb ambientAt(const std::vector<AmbientTerm>& terms, const std::vector<Eigen::Vector2d>& points,
                const vision::Pose& pose) const {
    Rgb sum;
    for (const AmbientTerm& term : terms) {
      std::optional<Rgb> value;
      if (term.pose) {
        const RegionMean own = regionMean(*term.frame, *term.pose, camera, points, 2.0);
        if (own.inside) value = own.value;
      }
      if (!value) value = regionMean(*term.frame, pose, camera, points, 2.0).value;
      sum += term.weight * *value;
    }
    return sum;
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
  const vision::RectMm& w = state_->target.window;
  const double half = settings.windowSampleFraction * std::min(w.widthMm(), w.heightMm()) / 2.0;
  const vision::PointMm c = w.centre();
  state_->windowPoints = gridPoints({c.xMm - half, c.yMm - half, c.xMm + half, c.yMm + half}, 9);
  // Each white patch gives up to 4 observations (its quarters), inset from the edges so a
  // slightly wrong pose or blur does not mix in the window or a marker.
  for (const auto& patch : state_->target.patches) {
    if (patch.kind != vision::PatchKind::White) continue;
    const vision::RectMm& r = patch.rect;
    const int nx = r.widthMm() > 2 * r.heightMm() ? 4 : (r.widthMm() * 2 < r.heightMm() ? 1 : 2);
    const int ny = r.heightMm() > 2 * r.widthMm() ? 4 : (r.heightMm() * 2 < r.widthMm() ? 1 : 2);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x0 = r.xMinMm + i * r.widthMm() / nx, x1 = x0 + r.widthMm() / nx;
        const double y0 = r.yMinMm + j * r.heightMm() / ny, y1 = y0 + r.heightMm() / ny;
        const double inset = 0.2 * std::min(x1 - x0, y1 - y0);
        const vision::RectMm part{x0 + inset, y0 + inset, x1 - inset, y1 - inset};
        state_->references.push_back(
            {gridPoints(part, 3), {part.centre().xMm, part.centre().yMm}, patch.albedo});
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
  if (badFrameDetail(frame, state_->camera.intrinsics)) return;
  state_->ambient = state_->makeAmbient(frame, false);
}

void FramePipeline::setFollowingAmbientFrame(const hal::Frame& frame) {
  State& s = *state_;
  if (badFrameDetail(frame, s.camera.intrinsics)) return;
  if (s.nextAmbient && s.nextAmbient->frame.metadata.timestampUs == frame.metadata.timestampUs)
    return;
  s.nextAmbient = s.makeAmbient(frame, false);
}

std::vector<AmbientTerm> FramePipeline::ambientTermsFor(std::int64_t timeUs) const {
  return state_->ambientTerms(timeUs);
}

FrameOutcome FramePipeline::process(const hal::Frame& frame, const SliceId& slice) {
  State& s = *state_;
  const std::uint64_t index = s.frameIndex++;
  if (auto detail = badFrameDetail(frame, s.camera.intrinsics))
    return rejected("bad_frame", std::move(*detail));
  if (!frame.metadata.ledOn) {
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
    return rejected("detection_deferred", markerText + " in this frame's detection budget",
                    outcome);
  if (m.markerCount < s.settings.minMarkers)
    return rejected("too_few_markers", markerText, outcome);
  const auto estimate = estimatePlanarPose(corners, s.camera);
  if (!estimate) return rejected("too_few_markers", markerText + ", no pose", outcome);
  const vision::Pose& pose = estimate->pose;
  m.pose = pose;
  if (estimate->residualRmsPx <= s.settings.maxPoseResidualPx) s.search.located(pose);
  const Eigen::Vector3d cameraCentre = pose.cameraCentreMm();
  m.poseResidualPx = estimate->residualRmsPx;
  m.cameraDistanceMm = cameraCentre.norm();
  if (cameraCentre.z() <= 0) return rejected("pose_residual", "camera below the target", outcome);
  m.view = vision::directionFrom(Eigen::Vector3d::Zero(), cameraCentre);
  outcome.viewElevationErrorDeg = m.view->thetaDeg - slice.elevations.thetaVDeg;
  const double phiLight = slice.kind == SliceKind::Axial
                              ? wrapDeg360(m.view->phiDeg - kAxialOffsetDeg)
                              : wrapDeg360(360.0 - m.view->phiDeg);
  m.nominalLight = Direction{static_cast<double>(slice.elevations.thetaIDeg), phiLight};
  if (m.poseResidualPx > s.settings.maxPoseResidualPx)
    return rejected("pose_residual", std::to_string(m.poseResidualPx) + " px", outcome);
  if (std::abs(*outcome.viewElevationErrorDeg) > s.settings.elevationToleranceDeg)
    return rejected("elevation_off", "view elevation " + std::to_string(m.view->thetaDeg) + " deg",
                    outcome);
  // Blur: motion smears the edges across the motion, so the blurriest quarter of the edges counts.
  const LinearView view(frame);
  std::vector<double> sharpness;
  for (const DetectedMarker* marker : known)
    for (int c = 0; c < 4; ++c) {
      const double value =
          edgeSharpness(view, marker->cornersPx[c], marker->cornersPx[(c + 1) % 4]);
      if (value >= 0) sharpness.push_back(value);
    }
  std::sort(sharpness.begin(), sharpness.end());
  m.sharpness = sharpness.empty() ? 0.0 : sharpness[sharpness.size() / 4];
  if (m.sharpness < s.settings.minSharpness)
    return rejected("blurred", "edge sharpness " + std::to_string(m.sharpness), outcome);

  const RegionMean window =
      regionMean(frame, pose, s.camera, s.windowPoints, s.settings.clipFraction);
  if (!window.inside) return rejected("window_occluded", "window out of the image", outcome);
  if (window.clipped) return rejected("window_clipped", "window saturated", outcome);
  // The same room-light term for the window and every reference, found once.
  // Without the LED alternating, an LED-off frame is a stray (a sweep's first): it would stand
  // for the room light of the whole sweep, read at pixels the camera has long moved from.
  const std::vector<AmbientTerm> ambient = s.settings.requireAmbient
                                               ? s.ambientTerms(frame.metadata.timestampUs)
                                               : std::vector<AmbientTerm>{};
  if (s.settings.requireAmbient && ambient.empty())
    return rejected("no_ambient_frame", "no LED-off frame yet", outcome);
  // Each frame is read per unit of exposure x gain; a frame whose camera reported none is read as
  // it is, which matches another such frame only (the same locked exposure assumed).
  for (const AmbientTerm& term : ambient)
    if (exposureKnown(*term.frame) != exposureKnown(frame))
      return rejected("no_ambient_frame",
                      exposureKnown(frame)
                          ? "the LED-off frame's exposure is unknown"
                          : "this frame's exposure is unknown, the LED-off frame's is not",
                      outcome);
  const Rgb windowRadiance = window.value - s.ambientAt(ambient, s.windowPoints, pose);
  std::vector<ReferenceObservation> observations;
  for (const auto& reference : s.references) {
    RegionMean area = regionMean(frame, pose, s.camera, reference.points, s.settings.clipFraction);
    if (!area.inside) continue;
    if (area.clipped) return rejected("window_clipped", "white reference saturated", outcome);
    area.value -= s.ambientAt(ambient, reference.points, pose);
    if (!(area.value.minChannel() > 0)) continue;
    observations.push_back(
        {{reference.centre.x(), reference.centre.y(), 0.0}, area.value, reference.albedo});
  }
  if (observations.size() < 5)
    return rejected("window_occluded", "white references out of the image", outcome);
  LightFitParams fitParams;
  const UnitVector toLight = toUnitVector(*m.nominalLight);
  fitParams.initialPositionMm = {toLight.x * s.settings.nominalLightDistanceMm,
                                 toLight.y * s.settings.nominalLightDistanceMm,
                                 toLight.z * s.settings.nominalLightDistanceMm};
  LightFit fit;
  try {
    fit = fitPointLight(observations, fitParams);
  } catch (const std::invalid_argument& error) {
    return rejected("window_occluded", error.what(), outcome);
  }
  if (!fit.converged || fit.relativeResidualRms > s.settings.maxReferenceResidual)
    return rejected("window_occluded",
                    "white references disagree by " + std::to_string(fit.relativeResidualRms),
                    outcome);
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
  outcome.kind = FrameOutcome::Kind::Sample;
  outcome.sample = sample;
  outcome.detail = markerText;
  return outcome;
}

FrameProcessor makeFramePipeline(const vision::TargetGeometry& target,
                                 const vision::CameraModel& camera,
                                 const PipelineSettings& settings,
                                 FrameObserver observer) {
  auto pipeline = std::make_shared<FramePipeline>(target, camera, settings);
  return [pipeline, observer = std::move(observer)](const hal::Frame& frame,
                                                    const SliceId& slice) {
    FrameOutcome outcome = pipeline->process(frame, slice);
    if (observer)
      observer(frame, outcome,
               frame.metadata.ledOn ? pipeline->ambientTermsFor(frame.metadata.timestampUs)
                                    : std::vector<AmbientTerm>{});
    return outcome;
  };
}

}  // namespace slicecap::capture
