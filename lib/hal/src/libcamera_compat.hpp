// The few places where Debian 12's libcamera 0.0.3 and the Raspberry Pi OS fork (0.1 and later)
// differ in API, kept here so the camera source compiles against both.
#pragma once

#include <libcamera/camera.h>
#include <libcamera/version.h>

#include <memory>
#include <vector>

namespace slicecap::hal::libcamera_compat {

/// 0.0.x takes `const StreamRoles&` (a std::vector); 0.1+ takes `Span<const StreamRole>`, which a
/// vector lvalue converts to. A braced list would compile only against one of them.
inline std::unique_ptr<libcamera::CameraConfiguration> generateConfiguration(
    libcamera::Camera& camera, libcamera::StreamRole role) {
  const std::vector<libcamera::StreamRole> roles{role};
  return camera.generateConfiguration(roles);
}

/// The rig needs frames as the sensor sees them: no flips. 0.0.x spells that
/// `transform = Identity`; 0.2+ replaced `transform` by `orientation`.
inline void keepSensorOrientation(libcamera::CameraConfiguration& configuration) {
#if LIBCAMERA_VERSION_MAJOR == 0 && LIBCAMERA_VERSION_MINOR < 2
  configuration.transform = libcamera::Transform::Identity;
#else
  configuration.orientation = libcamera::Orientation::Rotate0;
#endif
}

}  // namespace slicecap::hal::libcamera_compat
