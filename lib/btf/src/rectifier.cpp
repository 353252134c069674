// Rectification: texel points through the pose and the camera model, bilinear linear reads,
// ambient subtraction and irradiance normalisation per texel.
#include "slicecap/btf/rectifier.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "slicecap/capture/linear_view.hpp"

namespace slicecap::btf {
namespace {

// Sub-samples per texel side: about one per image pixel of the texel's footprint at the window
// centre (the largest of its projected sides).
int subsamplesOf(const TextureGrid& grid, const vision::CameraModel& camera,
                 const vision::Pose& pose, int maxSubsamples) {
  const int n = grid.resolution();
  const auto centre = camera.project(pose.toCamera(grid.pointMm(n / 2.0, n / 2.0)));
  const auto right = camera.project(pose.toCamera(grid.pointMm(n / 2.0 + 1.0, n / 2.0)));
  const auto down = camera.project(pose.toCamera(grid.pointMm(n / 2.0, n / 2.0 + 1.0)));
  if (!centre || !right || !down) return 1;
  const double footprintPx = std::max((*right - *centre).norm(), (*down - *centre).norm());
  return std::clamp(static_cast<int>(std::ceil(footprintPx)), 1, maxSubsamples);
}

}  // namespace

std::vector<float> rectifyFrame(const TextureGrid& grid, const vision::CameraModel& camera,
                                const hal::Frame& frame,
                                std::span<const capture::AmbientTerm> ambient,
                                const FrameGeometry& geometry, const RectifyParams& params) {
  const int n = grid.resolution();
  std::vector<float> out(grid.texelCount() * 3, std::numeric_limits<float>::quiet_NaN());
  const capture::CodeTable codes =
      params.toneCurve ? capture::CodeTable(*params.toneCurve) : capture::CodeTable::srgb();
  const capture::LinearView on(frame, codes);
  const auto perUsOf = [](const hal::Frame& f) {
    const double scale = f.metadata.exposureUs * f.metadata.gain;
    return 1.0 / (scale > 0 ? scale : 1.0);
  };
  struct Off {
    capture::LinearView view;
    const std::optional<vision::Pose>* pose;
    double weightPerUs;
  };
  std::vector<Off> offs;
  for (const capture::AmbientTerm& term : ambient)
    if (term.frame)
      offs.push_back(
          {capture::LinearView(*term.frame, codes), &term.pose, term.weight * perUsOf(*term.frame)});
  const double perUs = perUsOf(frame);
  const int s = subsamplesOf(grid, camera, geometry.pose, std::max(1, params.maxSubsamples));
  for (int row = 0; row < n; ++row) {
    for (int column = 0; column < n; ++column) {
      Rgb radiance;
      bool clipped = false, outside = false;
      for (int b = 0; b < s && !outside; ++b) {
        for (int a = 0; a < s; ++a) {
          const Eigen::Vector3d point = grid.pointMm(column + (a + 0.5) / s, row + (b + 0.5) / s);
          const auto px = camera.project(geometry.pose.toCamera(point));
          if (!px || !on.inside(*px)) {
            outside = true;
            break;
          }
          radiance += on.at(*px, params.clipFraction, &clipped) * perUs;
          for (const Off& off : offs) {
            // The same target point in the LED-off frame: through its own pose when located.
            Eigen::Vector2d at = *px;
            if (*off.pose) {
              const auto own = camera.project((*off.pose)->toCamera(point));
              if (own && off.view.inside(*own)) at = *own;
            }
            bool ignored = false;
            radiance -= off.view.at(at, 2.0, &ignored) * off.weightPerUs;
          }
        }
      }
      if (outside || clipped) continue;
      radiance *= 1.0 / (s * s);
      // The texel's own irradiance: the fitted point light at the texel's centre.
      const Eigen::Vector3d centre = grid.texelCentreMm(column, row);
      const Rgb irradiance = geometry.light.irradianceAt({centre.x(), centre.y(), 0.0});
      float* texel = &out[3 * grid.index(column, row)];
      for (int c = 0; c < 3; ++c)
        texel[c] = irradiance[c] > 0
                       ? static_cast<float>(std::max(0.0, radiance[c]) / irradiance[c])
                       : std::numeric_limits<float>::quiet_NaN();
    }
  }
  return out;
}

}  // namespace slicecap::btf
