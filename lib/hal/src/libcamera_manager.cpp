// libcamera's one CameraManager per process, the camera list and modes, and the helpers the
// camera's files share (formats offered, manual exposure controls, warnings said once).
#include <libcamera/control_ids.h>
#include <libcamera/property_ids.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <set>

#include "libcamera_compat.hpp"
#include "libcamera_state.hpp"

namespace slicecap::hal {
namespace libcamera_parts {
namespace {

// The manager and its users, counted under one lock: a new manager is made only after the last
// user has destroyed the old one (a weak_ptr would expire before its deleter finished, and a
// second manager made in that moment aborts the process).
std::mutex managerMutex;
libcamera::CameraManager* managerInstance = nullptr;
std::size_t managerUsers = 0;

void releaseCameraManager(libcamera::CameraManager*) {
  const std::lock_guard lock(managerMutex);
  if (--managerUsers > 0) return;
  managerInstance->stop();
  delete managerInstance;
  managerInstance = nullptr;
}

}  // namespace

std::shared_ptr<libcamera::CameraManager> sharedCameraManager() {
  const std::lock_guard lock(managerMutex);
  if (managerInstance == nullptr) {
    auto manager = std::make_unique<libcamera::CameraManager>();
    if (const int result = manager->start(); result != 0)
      throw CameraError(std::string("libcamera: cannot start the camera manager: ") +
                        std::strerror(-result));
    managerInstance = manager.release();
  }
  ++managerUsers;
  return std::shared_ptr<libcamera::CameraManager>(managerInstance, releaseCameraManager);
}

void warnOnce(const std::string& message) {
  static std::mutex mutex;
  static std::set<std::string> said;
  const std::lock_guard lock(mutex);
  if (said.insert(message).second) std::cerr << "slicecap: " << message << "\n";
}

void setManualExposure(libcamera::ControlList& controls, std::optional<double> exposureUs,
                       std::optional<double> gain) {
  controls.set(libcamera::controls::AeEnable, false);
  if (exposureUs)
    controls.set(libcamera::controls::ExposureTime,
                 static_cast<std::int32_t>(std::clamp(*exposureUs, 1.0, 2147483647.0)));
  if (gain) controls.set(libcamera::controls::AnalogueGain, static_cast<float>(*gain));
}

void setFrameDuration(libcamera::ControlList& controls, std::int64_t durationUs) {
  const std::array<std::int64_t, 2> limits{durationUs, durationUs};
  controls.set(libcamera::controls::FrameDurationLimits,
               libcamera::Span<const std::int64_t, 2>(limits));
}

std::vector<OfferedFormat> offeredFormatsOf(const libcamera::StreamConfiguration& stream) {
  std::vector<OfferedFormat> offered;
  for (const libcamera::PixelFormat& format : stream.formats().pixelformats()) {
    std::vector<std::pair<int, int>> sizes;
    for (const libcamera::Size& size : stream.formats().sizes(format))
      sizes.emplace_back(int(size.width), int(size.height));
    offered.push_back(offeredFormat(format.toString(), std::move(sizes)));
  }
  return offered;
}

}  // namespace libcamera_parts

using libcamera_parts::offeredFormatsOf;
using libcamera_parts::rawValidator;
using libcamera_parts::sharedCameraManager;

std::vector<std::string> listLibcameraCameras() {
  const std::shared_ptr<libcamera::CameraManager> manager = sharedCameraManager();
  std::vector<std::string> ids;
  for (const std::shared_ptr<libcamera::Camera>& camera : manager->cameras())
    ids.push_back(camera->id());
  return ids;
}

std::vector<CameraModes> listLibcameraModes(int wantedWidthPx, int wantedHeightPx) {
  const std::shared_ptr<libcamera::CameraManager> manager = sharedCameraManager();
  std::vector<CameraModes> cameras;
  for (const std::shared_ptr<libcamera::Camera>& camera : manager->cameras()) {
    CameraModes modes;
    modes.id = "libcamera: " + camera->id();
    modes.sensorModel = camera->properties().get(libcamera::properties::Model).value_or("");
    // generateConfiguration needs no acquire: a camera another process holds still lists.
    // The Raw role lists the sensor's RAW formats and modes; the processed formats come from
    // the role the sweep uses without RAW.
    if (auto raw = libcamera_compat::generateConfiguration(*camera, libcamera::StreamRole::Raw);
        raw && !raw->empty()) {
      for (OfferedFormat& format : offeredFormatsOf(raw->at(0)))
        if (format.raw) modes.formats.push_back(std::move(format));
      if (isRawFormatName(raw->at(0).pixelFormat.toString()))
        modes.proposedRawFormat = raw->at(0).pixelFormat.toString();
      // What a sweep's configure would be granted (validation needs no acquire either).
      if (std::any_of(modes.formats.begin(), modes.formats.end(),
                      [](const OfferedFormat& format) { return format.raw; }))
        modes.validatedRaw =
            negotiateRawStream(modes.formats, modes.proposedRawFormat, wantedWidthPx,
                               wantedHeightPx, rawValidator(*raw, 2));
    }
    if (auto video = libcamera_compat::generateConfiguration(*camera, libcamera::StreamRole::VideoRecording);
        video && !video->empty())
      for (OfferedFormat& format : offeredFormatsOf(video->at(0)))
        if (!format.raw) modes.formats.push_back(std::move(format));
    cameras.push_back(std::move(modes));
  }
  return cameras;
}

}  // namespace slicecap::hal
