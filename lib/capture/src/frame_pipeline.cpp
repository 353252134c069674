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
RegionMean regionMean(const hal::Frame& frame, const CodeTable& codes, const vision::Pose& pose,
                      const vision::CameraModel& camera, const std::vector<Eigen::Vector2d>& points,
                      double clipFraction) {
  const LinearView view(frame, codes);
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

int countKnown(const std::vector<DetectedMarker>& markers, const vision::TargetGeometry& target) {
  return static_cast<int>(std::count_if(markers.begin(), markers.end(), [&](const auto& m) {
    return target.findMarker(m.id) != nullptr;
  }));
}

// The image box of the sheet seen from `pose`, grown by 10 % of its size and 16 px on every side.
std::optional<PixelRect> sheetRegion(const vision::Pose& pose, const vision::CameraModel& camera,
                                     const vision::RectMm& sheet) {
  double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
  for (const double x : {sheet.xMinMm, sheet.xMaxMm})
    for (const double y : {sheet.yMinMm, sheet.yMaxMm}) {
      const auto px = camera.project(pose.toCamera({x, y, 0.0}));
      if (!px) return std::nullopt;
      x0 = std::min(x0, px->x()), x1 = std::max(x1, px->x());
      y0 = std::min(y0, px->y()), y1 = std::max(y1, px->y());
    }
  // 10 % and 16 px each side: between two LED-on frames of a simulated 48-frame sweep (15 deg
  // of azimuth apart, far more than at 30 frames/s) the sheet stayed inside (bench/capture_bench's
  // sweep cases: same samples as with 25 %, which cost 1.5-2x the time); a miss falls back.
  const double mx = 0.1 * (x1 - x0) + 16.0, my = 0.1 * (y1 - y0) + 16.0;
  return PixelRect{static_cast<int>(std::floor(x0 - mx)), static_cast<int>(std::floor(y0 - my)),
                   static_cast<int>(std::ceil(x1 - x0 + 2 * mx)),
                   static_cast<int>(std::ceil(y1 - y0 + 2 * my))};
}

// The markers in view at `pose` (all four corners project into the image): how many, and how
// each maps one tag cell to pixels near its corners 0 and 2 (the columns are the image vectors of
// a cell's two edges; at a grazing view the far edges are shorter than the near ones).
struct MarkersInView {
  int count = 0;
  std::vector<Eigen::Matrix2d> cellMaps;
};

MarkersInView markersInView(const vision::Pose& pose, const vision::CameraModel& camera,
                            const vision::TargetGeometry& target) {
  MarkersInView view;
  for (const vision::Marker& marker : target.markers) {
    std::array<Eigen::Vector2d, 4> px;
    bool inView = true;
    for (int c = 0; c < 4 && inView; ++c) {
      const auto p =
          camera.project(pose.toCamera({marker.cornersMm[c].xMm, marker.cornersMm[c].yMm, 0.0}));
      inView = p && p->x() >= 0 && p->y() >= 0 && p->x() < camera.intrinsics.widthPx &&
               p->y() < camera.intrinsics.heightPx;
      if (inView) px[c] = *p;
    }
    if (!inView) continue;
    ++view.count;
    Eigen::Matrix2d atFirst, atThird;
    atFirst << px[1] - px[0], px[3] - px[0];
    atThird << px[2] - px[3], px[2] - px[1];
    view.cellMaps.push_back(atFirst / vision::kTagBorderCells);
    view.cellMaps.push_back(atThird / vision::kTagBorderCells);
  }
  return view;
}

// The cheapest way to look at markers seen through `cellMaps`. First the library's decimations
// (3, 2, 1.5: quads found coarsely, corners refined at full resolution), the coarsest that leaves
// every cell at least minDecimatedCellPx across in any direction (the smaller singular value of
// the scaled map). Only when none does, binning along one axis (2-4 pixels averaged; the corners
// are refined at that resolution, measured worst corner 0.36 / 0.63 / 0.78 px at 2 / 3 / 4 x 1
// against 0.35 px at full resolution, and binned 4 x 4 the view error grew from 0.017 to 0.11 deg):
// the coarsest that leaves every cell minBinnedCellPx. Else full resolution. Decimation 4 is not
// offered: on a 30 deg frame it missed a tag and put a corner 3.8 px off
// (tests/capture/marker_detector_test.cpp).
DetectionScale trackedScale(const std::vector<Eigen::Matrix2d>& cellMaps,
                            const MarkerDetectorSettings& settings) {
  const auto smallestAcross = [&](double sx, double sy) {
    double smallest = 1e30;
    for (const Eigen::Matrix2d& map : cellMaps) {
      const Eigen::Matrix2d scaled = Eigen::Vector2d(1.0 / sx, 1.0 / sy).asDiagonal() * map;
      smallest = std::min(smallest, Eigen::JacobiSVD<Eigen::Matrix2d>(scaled).singularValues()(1));
    }
    return smallest;
  };
  if (cellMaps.empty()) return {};
  for (const float d : {3.0f, 2.0f, 1.5f})
    if (smallestAcross(d, d) >= settings.minDecimatedCellPx) return {d, 1, 1};
  for (int b = 4; b >= 2; --b)
    for (const auto& [bx, by] : {std::pair{b, 1}, std::pair{1, b}})
      if (smallestAcross(bx, by) >= settings.minBinnedCellPx) return {1.0f, bx, by};
  return {};
}

// LED-on frames without a pose after which tracking gives up on the last one.
constexpr int kTrackingPatienceFrames = 3;

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
  // settings.toneCurve's table, or sRGB's: how every 8-bit frame is read.
  std::shared_ptr<const CodeTable> codes;
  MarkerDetector detector;
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
  // The latest LED-on frame's pose, for tracking, kept over a few frames that were not located
  // (a blurred frame, the arm's shadow) so one bad frame does not cost a whole-frame search.
  std::optional<vision::Pose> lastPose;
  int framesSinceLastPose = 0;

  State(vision::TargetGeometry t, vision::CameraModel c, PipelineSettings s)
      : target(std::move(t)),
        camera(std::move(c)),
        settings(s),
        codes(s.toneCurve ? std::make_shared<const CodeTable>(*s.toneCurve)
                          : std::shared_ptr<const CodeTable>(&CodeTable::srgb(), [](auto*) {})),
        detector(s.detector) {}

  // Markers. Tracking from the latest pose: only the sheet's area, at the coarsest scale its tag
  // cells allow, accepted when it finds half the markers that pose had in view, else at full
  // resolution there; a miss (the target moved far, blur) searches the whole frame with the
  // detector's own settings before giving up. `trackedScale` tells which tracked pass was used.
  std::vector<DetectedMarker> detectMarkers(const hal::Frame& frame,
                                            std::optional<DetectionScale>* trackedScaleUsed) {
    if (trackedScaleUsed) trackedScaleUsed->reset();
    const std::optional<PixelRect> region =
        lastPose ? sheetRegion(*lastPose, camera, target.sheet) : std::nullopt;
    if (region) {
      const MarkersInView expected = markersInView(*lastPose, camera, target);
      const int enough = std::max(settings.minMarkers, (expected.count + 1) / 2);
      const DetectionScale scale = trackedScale(expected.cellMaps, settings.detector);
      std::vector<DetectedMarker> markers = detector.detect(frame, region, scale);
      DetectionScale used = scale;
      if (countKnown(markers, target) < enough &&
          (scale.quadDecimate > 1.0f || scale.binX > 1 || scale.binY > 1)) {
        std::vector<DetectedMarker> finer = detector.detect(frame, region, DetectionScale{});
        if (countKnown(finer, target) >= countKnown(markers, target)) {
          markers = std::move(finer);
          used = DetectionScale{};
        }
      }
      if (countKnown(markers, target) >= settings.minMarkers) {
        if (trackedScaleUsed) *trackedScaleUsed = used;
        return markers;
      }
    }
    return detector.detect(frame);
  }

  Ambient makeAmbient(const hal::Frame& frame) {
    Ambient a{frame, std::nullopt};
    if (!settings.poseAmbientFrames) return a;
    std::vector<PlaneCorrespondence> corners;
    for (const auto& marker : detectMarkers(frame, nullptr))
      if (const vision::Marker* geometry = target.findMarker(marker.id))
        for (int c = 0; c < 4; ++c)
          corners.push_back(
              {{geometry->cornersMm[c].xMm, geometry->cornersMm[c].yMm}, marker.cornersPx[c]});
    if (static_cast<int>(corners.size()) < 4 * settings.minMarkers) return a;
    const auto estimate = estimatePlanarPose(corners, camera);
    if (estimate && estimate->residualRmsPx <= settings.maxPoseResidualPx) a.pose = estimate->pose;
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
        const RegionMean own = regionMean(*term.frame, *codes, *term.pose, camera, points, 2.0);
        if (own.inside) value = own.value;
      }
      if (!value) value = regionMean(*term.frame, *codes, pose, camera, points, 2.0).value;
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
  state_->ambient = state_->makeAmbient(frame);
}

void FramePipeline::setFollowingAmbientFrame(const hal::Frame& frame) {
  State& s = *state_;
  if (badFrameDetail(frame, s.camera.intrinsics)) return;
  if (s.nextAmbient && s.nextAmbient->frame.metadata.timestampUs == frame.metadata.timestampUs)
    return;
  s.nextAmbient = s.makeAmbient(frame);
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
      s.ambient = s.makeAmbient(frame);
    }
    FrameOutcome outcome;
    outcome.kind = FrameOutcome::Kind::Ambient;
    return outcome;
  }
  FrameOutcome outcome;
  auto& m = outcome.measurement;
  // Tracking: search only where the sheet was in the latest located LED-on frame (plus a margin
  // for the hand's motion between frames), as coarsely as its tags allow; the detector's cost goes
  // with the pixels it is given, so this is what keeps a frame in budget (bench/capture_bench.cpp).
  // A miss there searches the whole frame before giving up.
  if (++s.framesSinceLastPose > kTrackingPatienceFrames) s.lastPose.reset();
  const std::vector<DetectedMarker> markers = s.detectMarkers(frame, &m.trackedScale);
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
  if (m.markerCount < s.settings.minMarkers)
    return rejected("too_few_markers", markerText, outcome);
  const auto estimate = estimatePlanarPose(corners, s.camera);
  if (!estimate) return rejected("too_few_markers", markerText + ", no pose", outcome);
  const vision::Pose& pose = estimate->pose;
  m.pose = pose;
  if (estimate->residualRmsPx <= s.settings.maxPoseResidualPx) {
    s.lastPose = pose;
    s.framesSinceLastPose = 0;
  }
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
  const LinearView view(frame, *s.codes);
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
      regionMean(frame, *s.codes, pose, s.camera, s.windowPoints, s.settings.clipFraction);
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
    RegionMean area =
        regionMean(frame, *s.codes, pose, s.camera, reference.points, s.settings.clipFraction);
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
