// Renders what the virtual rig's camera sees: the target lying flat on a desk, the material in its
// window, lit by a point LED and room light, through a pinhole camera with distortion.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "slicecap/core/image.hpp"
#include "slicecap/core/rgb.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/sim/rig.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::sim {

class PatternedMaterial;

/// \brief Accuracy and speed trade-offs of the renderer.
struct RenderSettings {
  double texelsPerMm = 5.0;  ///< the target's albedo raster (box-filtered, 4 x 4 samples a texel)
  int brdfGridNodes = 33;    ///< window radiance is exact on an N x N grid (odd: one node at the
                             ///< window centre) and bilinear between nodes
};

/// \brief One frame to render.
struct FrameScene {
  std::vector<vision::Pose> exposurePoses;  ///< averaged (motion blur); at least one
  Eigen::Vector3d lightMm = Eigen::Vector3d::Zero();
  bool ledOn = true;
  double exposureUs = 10000.0;
  double gain = 1.0;
  std::optional<Occluder> occluder;
  std::uint64_t noiseSeed = 0;
};

/// \brief The radiometry of one point, as the truth file states it.
struct PointRadiometry {
  double ledIrradiance = 0.0;  ///< W/m^2 from the LED (0 when it is off)
  Rgb brdf;                    ///< material BRDF, 1/sr, for the LED's and the camera's directions
  Rgb expectedLinear;          ///< noise-free linear pixel value (1 = full scale), LED + ambient
};

/// \brief Renders frames of one camera, target and material with one rig's radiometry. The
/// constructor precomputes every pixel's undistorted ray and the target's raster (~0.5 s); render
/// is const and thread-safe.
class FrameRenderer {
 public:
  FrameRenderer(vision::CameraModel camera, vision::TargetGeometry target,
                std::shared_ptr<const models::ReflectanceModel> material, const RigParams& rig,
                RenderSettings settings = {});

  /// \brief The frame, encoded as rig.encoding (RGB, 8-bit sRGB or 16-bit linear), with the rig's
  /// sensor noise drawn from scene.noiseSeed.
  Image render(const FrameScene& scene) const;

  /// \brief Noise-free linear RGB values (1 = full scale, not clipped), 3 floats a pixel.
  std::vector<float> renderLinear(const FrameScene& scene) const;

  /// \brief Exact radiometry of a target-plane window point seen from the scene's first pose.
  PointRadiometry windowPoint(const FrameScene& scene, const Eigen::Vector3d& pointMm) const;
  /// \brief The LED's irradiance (W/m^2) at a target-plane point, or 0 when it is off.
  double ledIrradiance(const FrameScene& scene, const Eigen::Vector3d& pointMm) const;
  /// \brief Pixel value per unit radiance: sensorResponse * exposure (s) * gain.
  double pixelScale(const FrameScene& scene) const;

  const vision::CameraModel& camera() const { return camera_; }
  const vision::TargetGeometry& target() const { return target_; }
  const models::ReflectanceModel& material() const { return *material_; }

 private:
  struct PoseState;
  PoseState prepare(const vision::Pose& pose, const FrameScene& scene, double scale) const;
  void accumulateRow(const PoseState& state, const FrameScene& scene, double scale, int row,
                     float* out) const;
  // Renders row by row (a row buffer stays in cache) and hands each finished row to `sink`.
  template <typename RowSink>
  void renderRows(const FrameScene& scene, RowSink&& sink) const;

  vision::CameraModel camera_;
  vision::TargetGeometry target_;
  std::shared_ptr<const models::ReflectanceModel> material_;
  const PatternedMaterial* pattern_ = nullptr;  // material_ as a pattern, if it is one
  RigParams rig_;
  RenderSettings settings_;
  std::vector<float> rays_;    // undistorted normalised (x, y) of every pixel
  std::vector<float> texels_;  // per texel: albedo r, g, b (printed fraction, plus desk), window
  int texWidth_ = 0, texHeight_ = 0;
  vision::RectMm texArea_;
};

}  // namespace slicecap::sim
