// The few places where Debian 12's libcamera 0.0.3 and the Raspberry Pi OS fork (0.1 and later)
// differ in API, kept here so the camera source compiles against both. Checked to be spelled the
// same in both, so used directly (0.0.3's headers and the fork's v0.7.1+rpt20260429
// control_ids_*.yaml, color_space.h, stream.h, pixel_format.h): controls::draft::NoiseReductionMode
// and NoiseReductionModeOff (draft in both), controls::Sharpness (float), controls::ColourGains
// (Span<const float, 2>), ColorSpace's YcbcrEncoding and Range, StreamConfiguration::colorSpace
// (std::optional<ColorSpace>) and PixelFormat::fromString.
#pragma once

#include <libcamera/camera.h>
#include <libcamera/control_ids.h>
#include <libcamera/controls.h>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace slicecap::hal::libcamera_compat {

/// 0.0.x takes `const StreamRoles&` (a std::vector); 0.1+ takes `Span<const StreamRole>`, which a
/// vector lvalue converts to. A braced list would compile only against one of them.
inline std::unique_ptr<libcamera::CameraConfiguration> generateConfiguration(
    libcamera::Camera& camera, libcamera::StreamRole role) {
  const std::vector<libcamera::StreamRole> roles{role};
  return camera.generateConfiguration(roles);
}

/// SensorBlackLevels is `Span<const int32_t, 4>` metadata in both (0.0.3's control_ids.h and the
/// fork's); ControlList::get returns std::optional in both. Levels on a 16-bit scale, R, Gr, Gb, B.
inline std::optional<std::array<double, 4>> sensorBlackLevels(const libcamera::ControlList& metadata) {
  const auto levels = metadata.get(libcamera::controls::SensorBlackLevels);
  if (!levels) return std::nullopt;
  return std::array<double, 4>{double((*levels)[0]), double((*levels)[1]), double((*levels)[2]),
                               double((*levels)[3])};
}

/// The rig needs frames as the sensor sees them: no flips. Debian's 0.0.x spells that
/// `transform = Identity`; upstream 0.2 replaced `transform` by `orientation`, and the Raspberry Pi
/// fork already has `orientation` in its 0.1.0 (Raspberry Pi OS bookworm's first libcamera), so the
/// version number cannot tell: the member is looked up. The enum types are named through the
/// member (dependent names), so the branch not taken is never looked up.
template <typename Configuration>
void keepSensorOrientation(Configuration& configuration) {
  if constexpr (requires { configuration.orientation; })
    configuration.orientation = decltype(configuration.orientation)::Rotate0;
  else
    configuration.transform = decltype(configuration.transform)::Identity;
}

}  // namespace slicecap::hal::libcamera_compat
