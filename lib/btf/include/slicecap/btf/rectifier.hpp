// One accepted frame's window rectified to the texture grid: a BRDF value per texel.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <vector>

#include "slicecap/btf/texture_grid.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/capture/light_model.hpp"
#include "slicecap/core/tone_curve.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"

namespace slicecap::btf {

/// \brief What rectifying a frame needs beyond its pixels: where the camera was and the light's
/// irradiance model (the point-light fit to the white references of the same frame).
struct FrameGeometry {
  vision::Pose pose;          ///< camera-from-target
  capture::PointLight light;  ///< irradiance at any target point, camera units per us
};

/// \brief Options of the rectification.
struct RectifyParams {
  /// \brief A texel with any sample at or above this fraction of full scale is left out (NaN).
  double clipFraction = 0.98;
  /// \brief Sub-samples per texel side are chosen so that they lie about one image pixel apart
  /// (a box filter over the texel's footprint), at most this many.
  int maxSubsamples = 4;
  /// \brief How 8-bit frames are decoded, as the pipeline that accepted them did
  /// (capture::PipelineSettings::toneCurve); nullopt: sRGB.
  std::optional<ToneCurve> toneCurve{};
};

/// \brief The frame's window on `grid`: per texel (row-major, R G B floats) the linear BRDF, 1/sr
/// = (LED-on radiance - LED-off radiance) / (exposure x gain) / the fitted irradiance at the
/// texel's own point. Each texel is the mean of sub-samples spread over its area, each projected
/// through the camera model with its distortion and read bilinearly. NaN where a texel leaves the
/// image or is clipped. `ambient` is the pipeline's room-light term for the frame
/// (FramePipeline::ambientTermsFor; empty: no subtraction): each LED-off frame read at the texel's
/// points through its own pose when it has one (the hand moved between the frames), else at the
/// LED-on frame's pixels, weighted as given.
std::vector<float> rectifyFrame(const TextureGrid& grid, const vision::CameraModel& camera,
                                const hal::Frame& frame,
                                std::span<const capture::AmbientTerm> ambient,
                                const FrameGeometry& geometry, const RectifyParams& params = {});

}  // namespace slicecap::btf
