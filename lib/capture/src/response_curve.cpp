// The bracket's measurement: each frame's pose from its markers, each reference area's mean code
// per channel over the pixels inside it, then the fit (response_solver.cpp).
#include "slicecap/capture/response_curve.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/linear_view.hpp"
#include "slicecap/capture/planar_pose.hpp"

namespace slicecap::capture {
namespace {

struct Area {
  vision::RectMm rect;
  Rgb albedo;
};

// Every white and black patch cut into areas about areaMm across, each inset from its edges.
std::vector<Area> referenceAreas(const vision::TargetGeometry& target,
                                 const ResponseFitParams& params) {
  std::vector<Area> areas;
  for (const vision::Patch& patch : target.patches) {
    const vision::RectMm& r = patch.rect;
    const int nx = std::max(1, static_cast<int>(std::lround(r.widthMm() / params.areaMm)));
    const int ny = std::max(1, static_cast<int>(std::lround(r.heightMm() / params.areaMm)));
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x0 = r.xMinMm + i * r.widthMm() / nx, x1 = x0 + r.widthMm() / nx;
        const double y0 = r.yMinMm + j * r.heightMm() / ny, y1 = y0 + r.heightMm() / ny;
        const double inset = params.insetFraction * std::min(x1 - x0, y1 - y0);
        areas.push_back({{x0 + inset, y0 + inset, x1 - inset, y1 - inset}, patch.albedo});
      }
  }
  return areas;
}

std::optional<vision::Pose> locate(const hal::Frame& frame, MarkerDetector& detector,
                                   const vision::TargetGeometry& target,
                                   const vision::CameraModel& camera,
                                   const ResponseFitParams& params) {
  std::vector<PlaneCorrespondence> corners;
  int markers = 0;
  for (const DetectedMarker& marker : detector.detect(frame))
    if (const vision::Marker* geometry = target.findMarker(marker.id)) {
      ++markers;
      for (int c = 0; c < 4; ++c)
        corners.push_back(
            {{geometry->cornersMm[c].xMm, geometry->cornersMm[c].yMm}, marker.cornersPx[c]});
    }
  if (markers < params.minMarkers) return std::nullopt;
  const auto estimate = estimatePlanarPose(corners, camera);
  if (!estimate || estimate->residualRmsPx > params.maxPoseResidualPx) return std::nullopt;
  return estimate->pose;
}

// Per channel: mean code, its standard error, and the fractions of pixels at 0 and at 255.
struct AreaCodes {
  int pixels = 0;
  std::array<std::array<std::uint32_t, 256>, 3> histogram{};
  std::array<double, 3> mean{}, standardError{}, atZero{}, atFull{};
};

// The pixels whose centres fall inside the area's image quadrilateral (the area is small: its
// edges stay straight through the lens's distortion to well under a pixel).
std::optional<AreaCodes> measureArea(const hal::Frame& frame, const vision::Pose& pose,
                                     const vision::CameraModel& camera, const Area& area) {
  const vision::RectMm& r = area.rect;
  std::array<Eigen::Vector2d, 4> quad;
  const std::array<std::array<double, 2>, 4> cornersMm{
      {{r.xMinMm, r.yMinMm}, {r.xMaxMm, r.yMinMm}, {r.xMaxMm, r.yMaxMm}, {r.xMinMm, r.yMaxMm}}};
  const Image& image = frame.image;
  for (int c = 0; c < 4; ++c) {
    const auto px = camera.project(pose.toCamera({cornersMm[c][0], cornersMm[c][1], 0.0}));
    if (!px || px->x() < 0 || px->y() < 0 || px->x() > image.width - 1 ||
        px->y() > image.height - 1)
      return std::nullopt;
    quad[c] = *px;
  }
  // Inside a convex quadrilateral: on the same side of all four edges.
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  const double orientation = cross(quad[1] - quad[0], quad[2] - quad[0]) > 0 ? 1.0 : -1.0;
  double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
  for (const auto& p : quad)
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()),
    y1 = std::max(y1, p.y());
  const int channels = image.channels >= 3 ? 3 : 1;
  std::array<double, 3> sum{}, sumSquares{};
  AreaCodes codes;
  for (int y = static_cast<int>(std::ceil(y0)); y <= static_cast<int>(std::floor(y1)); ++y)
    for (int x = static_cast<int>(std::ceil(x0)); x <= static_cast<int>(std::floor(x1)); ++x) {
      const Eigen::Vector2d p(x, y);
      bool inside = true;
      for (int e = 0; e < 4 && inside; ++e)
        inside = orientation * cross(quad[(e + 1) % 4] - quad[e], p - quad[e]) > 0;
      if (!inside) continue;
      ++codes.pixels;
      for (int c = 0; c < channels; ++c) {
        const double v = image.at(x, y, c);
        sum[c] += v;
        sumSquares[c] += v * v;
        ++codes.histogram[c][image.at(x, y, c) & 0xff];
        codes.atZero[c] += v == 0;
        codes.atFull[c] += v == 255;
      }
    }
  if (codes.pixels == 0) return std::nullopt;
  const double n = codes.pixels;
  for (int c = 0; c < channels; ++c) {
    codes.mean[c] = sum[c] / n;
    const double variance = std::max(0.0, sumSquares[c] / n - codes.mean[c] * codes.mean[c]);
    // Quantisation alone leaves 1/sqrt(12) of a code.
    codes.standardError[c] = std::max(std::sqrt(variance), 0.29) / std::sqrt(n);
    codes.atZero[c] /= n;
    codes.atFull[c] /= n;
  }
  return codes;
}

std::string framesText(const std::vector<hal::Frame>& bracket) {
  return std::to_string(bracket.size()) + " bracket frame" + (bracket.size() == 1 ? "" : "s") +
         (bracket.empty() ? std::string()
                          : " (sequence " + std::to_string(bracket.front().metadata.sequence) +
                                ".." + std::to_string(bracket.back().metadata.sequence) + ")");
}

// Throws ResponseFitError when the bracket has too few frames, or a frame is not an 8-bit frame
// of the camera's size or reports no exposure.
void checkBracketFrames(const std::vector<hal::Frame>& bracket, const vision::CameraModel& camera,
                        const ResponseFitParams& params, const std::string& source) {
  if (static_cast<int>(bracket.size()) < params.minExposures)
    throw ResponseFitError(source + ": too few exposures, at least " +
                           std::to_string(params.minExposures) +
                           " are needed (BracketPlan::factors)");
  for (const hal::Frame& frame : bracket) {
    const std::string name = params.cameraName + ", bracket frame " +
                             std::to_string(frame.metadata.sequence);
    if (frame.encoding != PixelEncoding::Srgb8 || frame.image.bitDepth != 8 ||
        !frame.image.isValid() || frame.image.width != camera.intrinsics.widthPx ||
        frame.image.height != camera.intrinsics.heightPx)
      throw ResponseFitError(name + ": not an 8-bit " + std::to_string(camera.intrinsics.widthPx) +
                             " x " + std::to_string(camera.intrinsics.heightPx) +
                             " frame (the response is measured on processed 8-bit frames)");
    if (!(frame.metadata.exposureUs * frame.metadata.gain > 0.0))
      throw ResponseFitError(name +
                             ": reports no exposure; the bracket needs each frame's exposure and "
                             "gain (a camera that does not say them cannot be bracketed: decode "
                             "as sRGB, or use a camera that reports them)");
  }
}

// A frame too dark for its markers takes the nearest located frame's pose (at least one is).
std::size_t nearestLocatedFrame(const std::vector<std::optional<vision::Pose>>& poses,
                                std::size_t f) {
  std::size_t from = f;
  for (std::size_t d = 0; !poses[from]; ++d) {
    if (f >= d && poses[f - d])
      from = f - d;
    else if (f + d < poses.size() && poses[f + d])
      from = f + d;
  }
  return from;
}

// One observation per reference area and channel of `frame` seen from `pose`, with its histogram.
void observeFrameAreas(const hal::Frame& frame, const vision::Pose& pose,
                       const vision::CameraModel& camera, const std::vector<Area>& areas,
                       const ResponseFitParams& params, BracketObservations& measured) {
  const double exposure = frame.metadata.exposureUs * frame.metadata.gain;
  const int channels = frame.image.channels >= 3 ? 3 : 1;
  for (std::size_t a = 0; a < areas.size(); ++a) {
    const auto codes = measureArea(frame, pose, camera, areas[a]);
    if (!codes || codes->pixels < params.minPixels) continue;
    for (int c = 0; c < channels; ++c) {
      ResponseObservation o;
      o.area = static_cast<int>(a) * 3 + c;
      o.code = codes->mean[c];
      o.exposure = exposure;
      o.albedo = channels == 3 ? areas[a].albedo[c] : areas[a].albedo.mean();
      // A clamp at 0 or 255 biases the mean: such an area is left out, as a clipped one.
      const bool clamped = codes->atZero[c] > 0.01 || codes->atFull[c] > 0.01;
      if (clamped) o.code = codes->atFull[c] > 0.01 ? 255.0 : 0.0;
      o.weight = clamped ? 1.0 : o.code / codes->standardError[c];
      measured.observations.push_back(o);
      measured.histograms.push_back(codes->histogram[c]);
    }
  }
}

}  // namespace

BracketObservations measureBracket(const std::vector<hal::Frame>& bracket,
                                   const vision::TargetGeometry& target,
                                   const vision::CameraModel& camera,
                                   const ResponseFitParams& params) {
  std::string why;
  if (!params.isValid(&why)) throw CaptureError(why);
  const std::string source = params.cameraName + ", " + framesText(bracket);
  checkBracketFrames(bracket, camera, params, source);
  const std::vector<Area> areas = referenceAreas(target, params);
  MarkerDetector detector(params.detector);
  std::vector<std::optional<vision::Pose>> poses;
  for (const hal::Frame& frame : bracket)
    poses.push_back(locate(frame, detector, target, camera, params));
  BracketObservations measured;
  measured.source = source;
  for (const auto& pose : poses) measured.framesWithOwnPose += pose.has_value();
  if (measured.framesWithOwnPose == 0)
    throw ResponseFitError(source + ": the target was not found in any frame (at least " +
                           std::to_string(params.minMarkers) +
                           " markers and a pose): put the whole target in view, the LED on");
  for (std::size_t f = 0; f < bracket.size(); ++f)
    observeFrameAreas(bracket[f], *poses[nearestLocatedFrame(poses, f)], camera, areas, params,
                      measured);
  return measured;
}

ResponseFit fitResponse(const std::vector<hal::Frame>& bracket, const vision::TargetGeometry& target,
                        const vision::CameraModel& camera, const ResponseFitParams& params) {
  BracketObservations measured = measureBracket(bracket, target, camera, params);
  ResponseFit fit = fitResponseCurve(measured.observations, params, measured.source);
  for (int round = 0; round < 2; ++round) {
    const CodeTable codes(fit.curve);
    for (std::size_t i = 0; i < measured.observations.size(); ++i) {
      ResponseObservation& o = measured.observations[i];
      if (o.code <= params.darkCode || o.code >= params.clipCode) continue;  // left out anyway
      double sum = 0.0, count = 0.0;
      for (int code = 0; code < 256; ++code) {
        sum += measured.histograms[i][code] * codes[static_cast<std::uint16_t>(code)];
        count += measured.histograms[i][code];
      }
      o.code = std::clamp(255.0 * fit.curve.encode(sum / count), params.darkCode + 1e-3,
                          params.clipCode - 1e-3);
    }
    fit = fitResponseCurve(measured.observations, params, measured.source);
  }
  fit.framesWithOwnPose = measured.framesWithOwnPose;
  // A curve that does not fit is refused, not used (issue 44).
  checkResponseResidual(fit, params, measured.source);
  return fit;
}

}  // namespace slicecap::capture
