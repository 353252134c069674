// The frame pipeline's checks of one frame that need no pipeline state.
#include "frame_checks.hpp"

#include <algorithm>
#include <cmath>

namespace slicecap::capture::frame_checks {
namespace {

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

}  // namespace

bool exposureKnown(const hal::Frame& frame) {
  return frame.metadata.exposureUs * frame.metadata.gain > 0;
}

double noiseAllowance(const LightFit& fit, double sigmas) {
  if (fit.degreesOfFreedom <= 0 || fit.noiseResidualRms <= 0) return 0.0;
  const double h = 2.0 / (9.0 * fit.degreesOfFreedom);
  const double cubeRoot = std::max(0.0, 1.0 - h + sigmas * std::sqrt(h));
  return fit.noiseResidualRms * std::pow(cubeRoot, 1.5);
}

double blurSharpness(const LinearView& view, const std::vector<const DetectedMarker*>& markers) {
  std::vector<double> sharpness;
  for (const DetectedMarker* marker : markers)
    for (int c = 0; c < 4; ++c) {
      const double value =
          edgeSharpness(view, marker->cornersPx[c], marker->cornersPx[(c + 1) % 4]);
      if (value >= 0) sharpness.push_back(value);
    }
  std::sort(sharpness.begin(), sharpness.end());
  return sharpness.empty() ? 0.0 : sharpness[sharpness.size() / 4];
}

std::string ledTransitionDetail(const RowSpan& rows) {
  return "the LED switched while rows " + std::to_string(rows.first) + ".." +
         std::to_string(rows.last) + " were exposed";
}

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

FrameOutcome rejected(RejectReason reason, std::string detail, FrameOutcome outcome) {
  outcome.kind = FrameOutcome::Kind::Rejected;
  outcome.sample.reset();
  outcome.rejectReason = reason;
  outcome.detail = std::move(detail);
  return outcome;
}

}  // namespace slicecap::capture::frame_checks
