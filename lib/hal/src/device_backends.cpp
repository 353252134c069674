// The backend factories: the device where the build has its backend, else the error naming the
// CMake option. The only file that knows the SLICECAP_HAS_* definitions (lib/hal/CMakeLists.txt).
#include "slicecap/hal/device_backends.hpp"

#if SLICECAP_HAS_LIBCAMERA
#include "slicecap/hal/libcamera_camera.hpp"
#endif
#if SLICECAP_HAS_V4L2
#include "slicecap/hal/v4l2_camera.hpp"
#endif

namespace slicecap::hal {
namespace {

// The Debian package each backend builds against, for the error's advice.
std::string backendPackage(DeviceBackend backend) {
  switch (backend) {
    case DeviceBackend::Libcamera:
      return "libcamera-dev";
    case DeviceBackend::V4l2:
      return "the Linux kernel headers";
    case DeviceBackend::Gpiod:
      return "libgpiod-dev";
  }
  return "its library";
}

std::string notBuiltMessage(DeviceBackend backend) {
  const std::string option = backendOption(backend);
  return backendName(backend) + ": not in this build (configured with -D" + option +
         "=OFF): rebuild with -D" + option + "=ON (needs " + backendPackage(backend) + ")";
}

}  // namespace

std::string backendName(DeviceBackend backend) {
  switch (backend) {
    case DeviceBackend::Libcamera:
      return "libcamera";
    case DeviceBackend::V4l2:
      return "v4l2";
    case DeviceBackend::Gpiod:
      return "libgpiod";
  }
  return "unknown backend";
}

std::string backendOption(DeviceBackend backend) {
  switch (backend) {
    case DeviceBackend::Libcamera:
      return "SLICECAP_WITH_LIBCAMERA";
    case DeviceBackend::V4l2:
      return "SLICECAP_WITH_V4L2";
    case DeviceBackend::Gpiod:
      return "SLICECAP_WITH_GPIOD";
  }
  return "SLICECAP_WITH_?";
}

bool isBuilt(DeviceBackend backend) {
  switch (backend) {
    case DeviceBackend::Libcamera:
      return SLICECAP_HAS_LIBCAMERA;
    case DeviceBackend::V4l2:
      return SLICECAP_HAS_V4L2;
    case DeviceBackend::Gpiod:
      return SLICECAP_HAS_GPIOD;
  }
  return false;
}

BackendNotBuilt::BackendNotBuilt(DeviceBackend backend)
    : slicecap::Error(notBuiltMessage(backend)), backend_(backend) {}

void requireBuilt(DeviceBackend backend) {
  if (!isBuilt(backend)) throw BackendNotBuilt(backend);
}

std::shared_ptr<Camera> openLibcameraCamera([[maybe_unused]] const std::string& cameraId) {
#if SLICECAP_HAS_LIBCAMERA
  return std::make_shared<LibcameraCamera>(cameraId);
#else
  throw BackendNotBuilt(DeviceBackend::Libcamera);
#endif
}

std::vector<CameraModes> libcameraModes([[maybe_unused]] int wantedWidthPx,
                                        [[maybe_unused]] int wantedHeightPx) {
#if SLICECAP_HAS_LIBCAMERA
  return listLibcameraModes(wantedWidthPx, wantedHeightPx);
#else
  throw BackendNotBuilt(DeviceBackend::Libcamera);
#endif
}

std::shared_ptr<Camera> openV4l2Camera([[maybe_unused]] const std::filesystem::path& device) {
#if SLICECAP_HAS_V4L2
  return std::make_shared<V4l2Camera>(device);
#else
  throw BackendNotBuilt(DeviceBackend::V4l2);
#endif
}

CameraModes v4l2Modes([[maybe_unused]] const std::string& devicePath) {
#if SLICECAP_HAS_V4L2
  return listV4l2Modes(devicePath);
#else
  throw BackendNotBuilt(DeviceBackend::V4l2);
#endif
}

std::unique_ptr<Led> openGpiodLed([[maybe_unused]] const GpioLineSpec& spec) {
#if SLICECAP_HAS_GPIOD
  return std::make_unique<GpiodLed>(spec);
#else
  throw BackendNotBuilt(DeviceBackend::Gpiod);
#endif
}

}  // namespace slicecap::hal
