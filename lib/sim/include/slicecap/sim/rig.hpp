// The virtual rig's motion: where the camera and the LED are for every frame of a sweep, with the
// imperfections of a hand-held capture.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/core/pixel_encoding.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::sim {

/// \brief How the rig moves and what goes wrong. Lengths in mm, angles in degrees, fractions of
/// frames in [0, 1]. Radiometry: the LED's irradiance at a point is ledIntensity * cos(theta_i) /
/// d^2 (d in m, W/m^2 for intensity in W/sr); a pixel's linear value (1 = full scale) is
/// sensorResponse * exposure (s) * gain * radiance (W / (m^2 sr)).
struct RigParams {
  int framesPerSlice = 48;          ///< frames over the 360 deg sweep
  double sweepSeconds = 12.0;       ///< time for one sweep (sets the timestamps)
  double cameraDistanceMm = 300.0;  ///< from the window centre
  double lightDistanceMm = 300.0;   ///< LED to window centre
  double ledIntensityWPerSr = 1.0;
  double sensorResponse = 20.0;    ///< full scale per (W / (m^2 sr) * s)
  double ambientIrradiance = 0.3;  ///< W/m^2 of diffuse room light (the LED gives ~10)
  double deskAlbedo = 0.25;        ///< the desk around the sheet
  std::optional<double>
      exposureUs;  ///< nullopt: metered (chooseExposureUs, or the HDR levels of chooseHdrLevelsUs)
  /// \brief What a single metered exposure puts at 80 % of full scale: the brightest of the window
  /// centre and the white references (Brightest), or the white references alone (Paper: what a
  /// camera metering on the sheet does; a sharp highlight then clips).
  enum class Metering { Brightest, Paper };
  Metering metering = Metering::Brightest;
  /// \brief HDR: at most this many exposure levels (1..3) alternated by LED pair over the sweep,
  /// chosen by chooseHdrLevelsUs; the sweep then has framesPerSlice frames per level. 1: one
  /// exposure, as before.
  int maxExposureLevels = 1;
  double gain = 1.0;
  PixelEncoding encoding = PixelEncoding::Srgb8;
  bool alternateLed = true;  ///< every second frame with the LED off (ambient subtraction)

  // Imperfections (set by realistic(); all zero in ideal()).
  double elevationJitterDeg = 0.0;      ///< camera elevation, standard deviation
  double azimuthJitterDeg = 0.0;        ///< camera position along the sweep, standard deviation
  double distanceJitterMm = 0.0;        ///< camera distance, standard deviation
  double aimJitterMm = 0.0;             ///< where the camera points, around the window centre
  double rollJitterDeg = 0.0;           ///< camera roll about its axis
  double lightElevationErrorDeg = 0.0;  ///< the arm's actual light elevation minus nominal
  double motionBlurFraction = 0.0;      ///< frames with motion blur
  double motionBlurMaxPx = 0.0;         ///< blur length up to this, pixels at the window
  double readNoise = 0.0;               ///< read noise, fraction of full scale (standard deviation)
  double fullWellElectrons = 0.0;       ///< shot noise: electrons at full scale (0 = none)
  double exposureChangeFraction = 0.0;  ///< LED pairs taken at a lower exposure (x0.5 .. x0.9)
  double occlusionFraction = 0.0;       ///< frames where the light arm hides part of the window
  double markersOutOfViewFraction =
      0.0;  ///< frames aimed so that part of the target leaves the image
  std::uint64_t seed = 1;

  /// \brief No imperfections: the camera exactly on the slice, no noise, no blur.
  static RigParams ideal();
  /// \brief A careful person with a hand-held camera: elevation within ~2 deg, 1 in 10 frames
  /// blurred, 1 in 20 occluded or partly out of view, some exposure changes, sensor noise.
  static RigParams realistic();
  /// \brief realistic()'s sensor and room light (noise as on an 8-bit sensor) without the hand's
  /// imperfections (jitter, blur, occlusion, exposure changes, markers out of view): what the
  /// exposure alone costs.
  static RigParams steady();

  /// \brief False with a reason naming the field for a value out of range.
  bool isValid(std::string* error = nullptr) const;
};

/// \brief A quadrilateral in image pixels that hides what is behind it (the light arm).
struct Occluder {
  std::array<Eigen::Vector2d, 4> cornersPx;
};

/// \brief Everything about one frame before it is rendered.
struct FramePlan {
  int index = 0;
  std::int64_t timestampUs = 0;
  double sliceParameterDeg = 0.0;           ///< nominal position on the slice
  vision::Pose pose;                        ///< at mid-exposure
  std::vector<vision::Pose> exposurePoses;  ///< poses through the exposure (one when sharp)
  Eigen::Vector3d lightMm = Eigen::Vector3d::Zero();
  bool ledOn = true;
  double exposureScale = 1.0;  ///< this frame's exposure relative to the sweep's base exposure
  double exposureUs = 0.0;     ///< 0 until the sweep's base exposure is chosen
  int exposureLevel = 0;       ///< HDR: the level of the sweep's exposure cycle (0 = longest)
  double gain = 1.0;
  std::optional<Occluder> occluder;
  bool aimedOff = false;  ///< aimed so that some markers leave the image (the window stays in)
};

/// \brief The frames of one sweep: the slice's parameter goes once around (0..360), the light at
/// theta_i and, for an axial slice, phi_i = parameter with the camera at phi_v = phi_i + alpha;
/// for a diagonal one the camera at phi_v = parameter and the light at phi_i = 360 - phi_v. All
/// randomness comes from params.seed and the slice, so a plan is reproducible. `bracketLevels`
/// (1..3, an HDR sweep's exposure levels) takes each position with that many consecutive LED
/// pairs (framesPerSlice x bracketLevels frames), each drawing its own hand-held imperfections.
/// Throws SimError for invalid parameters.
std::vector<FramePlan> planSweep(const SliceId& slice, double alphaDeg, const RigParams& params,
                                 const vision::CameraModel& camera,
                                 const vision::TargetGeometry& target, int bracketLevels = 1);

}  // namespace slicecap::sim
