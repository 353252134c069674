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

// Linear values per microsecond of exposure (and unit gain) from a frame's values.
double perUsOf(const hal::Frame& f) {
  const double scale = f.metadata.exposureUs * f.metadata.gain;
  return 1.0 / (scale > 0 ? scale : 1.0);
}

// An LED-off frame to subtract: its linear view, its own pose when located, its weight per us.
struct OffFrame {
  capture::LinearView view;
  const std::optional<vision::Pose>* pose;
  double weightPerUs;
};

std::vector<OffFrame> ambientViews(std::span<const capture::AmbientTerm> ambient,
                                   const capture::CodeTable& codes) {
  std::vector<OffFrame> offs;
  for (const capture::AmbientTerm& term : ambient)
    if (term.frame)
      offs.push_back({capture::LinearView(*term.frame, codes), &term.pose,
                      term.weight * perUsOf(*term.frame)});
  return offs;
}

// One texel's s x s sub-samples in the LED-on frame, the room light of the LED-off frames
// subtracted.
struct TexelSampler {
  const TextureGrid& grid;
  const vision::CameraModel& camera;
  const vision::Pose& pose;
  const capture::LinearView& on;
  const std::vector<OffFrame>& offs;
  double perUs;
  double clipFraction;
  int s;

  // The sum over the sub-samples into `radiance` (`clipped` set when one is); false when a
  // sub-sample falls outside the frame.
  bool sum(int column, int row, Rgb& radiance, bool& clipped) const {
    for (int b = 0; b < s; ++b) {
      for (int a = 0; a < s; ++a) {
        const Eigen::Vector3d point = grid.pointMm(column + (a + 0.5) / s, row + (b + 0.5) / s);
        const auto px = camera.project(pose.toCamera(point));
        if (!px || !on.inside(*px)) return false;
        radiance += on.at(*px, clipFraction, &clipped) * perUs;
        for (const OffFrame& off : offs) {
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
    return true;
  }
};

// The texel's BRDF-like value: the mean radiance over its own irradiance, the fitted point light
// at the texel's centre (NaN where that is not positive); scales `radiance` to the mean in place.
void storeTexel(const TextureGrid& grid, const capture::PointLight& light, int column, int row,
                Rgb& radiance, int s, std::vector<float>& out) {
  radiance *= 1.0 / (s * s);
  const Eigen::Vector3d centre = grid.texelCentreMm(column, row);
  const Rgb irradiance = light.irradianceAt({centre.x(), centre.y(), 0.0});
  float* texel = &out[3 * grid.index(column, row)];
  for (int c = 0; c < 3; ++c)
    texel[c] = irradiance[c] > 0 ? static_cast<float>(std::max(0.0, radiance[c]) / irradiance[c])
                                 : std::numeric_limits<float>::quiet_NaN();
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
  const std::vector<OffFrame> offs = ambientViews(ambient, codes);
  const double perUs = perUsOf(frame);
  const int s = subsamplesOf(grid, camera, geometry.pose, std::max(1, params.maxSubsamples));
  const TexelSampler sampler{grid, camera, geometry.pose, on, offs, perUs, params.clipFraction, s};
  for (int row = 0; row < n; ++row) {
    for (int column = 0; column < n; ++column) {
      Rgb radiance;
      bool clipped = false;
      if (!sampler.sum(column, row, radiance, clipped) || clipped) continue;
      storeTexel(grid, geometry.light, column, row, radiance, s, out);
    }
  }
  return out;
}

}  // namespace slicecap::btf
