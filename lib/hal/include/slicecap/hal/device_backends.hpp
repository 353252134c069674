// The hardware backends a build may leave out (SLICECAP_WITH_*), and how slicecapd opens them.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "slicecap/core/error.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/gpiod_led.hpp"
#include "slicecap/hal/led.hpp"

namespace slicecap::hal {

/// \brief A device backend that needs a library or kernel interface a build may not have.
enum class DeviceBackend { Libcamera, V4l2, Gpiod };

/// \brief "libcamera", "v4l2", "libgpiod".
std::string backendName(DeviceBackend backend);
/// \brief The CMake option that builds it: "SLICECAP_WITH_LIBCAMERA", ...
std::string backendOption(DeviceBackend backend);
/// \brief Whether this build has the backend (its option was ON when it was configured).
bool isBuilt(DeviceBackend backend);

/// \brief A backend this build does not have was asked for. what() names the backend and the CMake
/// option that builds it, e.g. "libcamera: not in this build (configured with
/// -DSLICECAP_WITH_LIBCAMERA=OFF): rebuild with -DSLICECAP_WITH_LIBCAMERA=ON (needs libcamera-dev)".
class BackendNotBuilt : public slicecap::Error {
 public:
  explicit BackendNotBuilt(DeviceBackend backend);
  DeviceBackend backend() const { return backend_; }

 private:
  DeviceBackend backend_;
};

/// \brief Throws BackendNotBuilt unless isBuilt(backend).
void requireBuilt(DeviceBackend backend);

// The factories: the backend's device when it is built, else BackendNotBuilt. Past that, each
// throws what its device's constructor or lister throws (libcamera_camera.hpp, v4l2_camera.hpp,
// gpiod_led.hpp).

/// \brief A LibcameraCamera with this id ("" for the first camera).
std::shared_ptr<Camera> openLibcameraCamera(const std::string& cameraId);
/// \brief listLibcameraModes(wantedWidthPx, wantedHeightPx).
std::vector<CameraModes> libcameraModes(int wantedWidthPx, int wantedHeightPx);
/// \brief A V4l2Camera on this device node.
std::shared_ptr<Camera> openV4l2Camera(const std::filesystem::path& device);
/// \brief listV4l2Modes(devicePath).
CameraModes v4l2Modes(const std::string& devicePath);
/// \brief A GpiodLed on this line.
std::unique_ptr<Led> openGpiodLed(const GpioLineSpec& spec);

}  // namespace slicecap::hal
