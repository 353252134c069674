// `slicecapd --check-hardware`'s description of the configured camera backend: the cameras'
// modes, and what the RAW setting will do with the camera the sweep opens.
#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/device_backends.hpp"
#include "slicecap/rig/check_hardware.hpp"

namespace slicecap::rig {
namespace {

namespace fs = std::filesystem;
using daemon::DaemonConfig;

void addModes(hwcheck::BackendInfo& info, const hal::CameraModes& modes) {
  for (std::string& line : hal::describeModes(modes)) info.cameras.push_back(std::move(line));
}

// What the RAW setting will do with the camera the sweep opens, before the check configures it:
// said when the camera delivers no RAW stream (the check's RAW item then stands as this).
void describeRaw(hwcheck::BackendInfo& info, const DaemonConfig& config,
                 const hal::CameraModes* camera) {
  // libcamera's listing says what the camera's validation grants, as configure negotiates it
  // (a Pi 5's unpacked SRGGB16); other backends list names only.
  const auto& raw = camera ? camera->formats : std::vector<hal::OfferedFormat>{};
  const hal::RawStreamChoice choice =
      camera && camera->validatedRaw
          ? *camera->validatedRaw
          : hal::chooseRawStream(raw, camera ? camera->proposedRawFormat : "", config.widthPx,
                                 config.heightPx);
  std::string validation;
  for (const std::string& note : choice.notes) validation += "; " + note;
  if (!choice.format.empty() && config.cameraRaw == hal::RawCapture::Off) {
    info.rawFinding = "the camera offers RAW " + choice.format + " (" +
                      std::to_string(choice.modePx.first) + "x" + std::to_string(choice.modePx.second) +
                      validation + "), but camera_raw = off: frames are the ISP's processed output";
    info.rawAdvice = "set camera_raw = auto to measure linear light from the sensor";
  } else if (!choice.format.empty()) {
    info.rawFinding = "the camera offers RAW " + choice.format +
                      (validation.empty() ? "" : " (" + validation.substr(2) + ")") +
                      ", but did not deliver it (see the camera item): frames are processed";
    info.rawAdvice = "frames are decoded through the measured response curve; with camera_raw = on "
                     "the configure error names the cause";
  } else {
    info.rawFinding = (camera ? choice.reason : std::string("the camera's formats could not be listed")) +
                      ": frames are the camera's processed output";
    info.rawAdvice = "frames are decoded through the measured response curve below";
  }
}

// The libcamera cameras' modes, and the RAW finding for the one the sweep opens.
void describeLibcameraBackend(hwcheck::BackendInfo& info, const DaemonConfig& config) {
  std::vector<hal::CameraModes> cameras;
  try {
    cameras = hal::libcameraModes(config.widthPx, config.heightPx);
  } catch (const hal::BackendNotBuilt& error) {
    info.cameras.push_back(error.what());
  } catch (const std::exception& error) {
    info.cameras.push_back(std::string("libcamera: cannot list: ") + error.what());
  }
  if (cameras.empty() && info.cameras.empty()) info.cameras.push_back("libcamera: no camera found");
  const hal::CameraModes* used = nullptr;
  for (const hal::CameraModes& modes : cameras) {
    addModes(info, modes);
    if (!used && (config.cameraDevice.empty() || modes.id == "libcamera: " + config.cameraDevice))
      used = &modes;
  }
  describeRaw(info, config, used);
}

// Every /dev/video* node's modes, and the RAW finding for the one the sweep opens.
void describeV4l2Backend(hwcheck::BackendInfo& info, const DaemonConfig& config) {
  const std::string device = config.cameraDevice.empty() ? "/dev/video0" : config.cameraDevice;
  if (!hal::isBuilt(hal::DeviceBackend::V4l2)) {
    info.cameras.push_back(hal::BackendNotBuilt(hal::DeviceBackend::V4l2).what());
    describeRaw(info, config, nullptr);
    return;
  }
  std::optional<hal::CameraModes> used;
  std::error_code error;
  std::vector<fs::path> nodes;
  for (const fs::directory_entry& entry : fs::directory_iterator("/dev", error))
    if (entry.path().filename().string().rfind("video", 0) == 0) nodes.push_back(entry.path());
  std::sort(nodes.begin(), nodes.end());
  for (const fs::path& node : nodes) {
    try {
      hal::CameraModes modes = hal::v4l2Modes(node.string());
      addModes(info, modes);
      if (node == device) used = std::move(modes);
    } catch (const std::exception& listError) {
      // Bridges such as the Pi's unicam expose metadata nodes: named, not a failure.
      info.cameras.push_back(std::string("v4l2: ") + listError.what());
    }
  }
  if (nodes.empty()) info.cameras.push_back("v4l2: no /dev/video* device");
  describeRaw(info, config, used ? &*used : nullptr);
}

// The model camera's stream (and RAW stream where model_raw names one), as it offers them.
void describeModelBackend(hwcheck::BackendInfo& info, const DaemonConfig& config) {
  hal::CameraModes modes;
  modes.id = "model camera: a Pi camera module 3 behind the Pi's ISP (tone curve " +
             config.modelToneCurve + "), 30 fps, over the virtual rig";
  modes.formats.push_back(hal::offeredFormat("RGB888", {{config.widthPx, config.heightPx}}));
  if (!config.modelRaw.empty()) {
    modes.formats.push_back(
        hal::offeredFormat(config.modelRaw, {{2 * config.widthPx, 2 * config.heightPx}}));
    modes.proposedRawFormat = config.modelRaw;
  }
  addModes(info, modes);
  describeRaw(info, config, &modes);
}

}  // namespace

hwcheck::BackendInfo describeBackend(const DaemonConfig& config) {
  hwcheck::BackendInfo info;
  switch (config.camera) {
    case DaemonConfig::CameraKind::Libcamera:
      describeLibcameraBackend(info, config);
      break;
    case DaemonConfig::CameraKind::V4l2:
      describeV4l2Backend(info, config);
      break;
    case DaemonConfig::CameraKind::Model:
      describeModelBackend(info, config);
      break;
    case DaemonConfig::CameraKind::File:
      info.cameras.push_back("file camera: plays " + config.recording.string());
      info.rawFinding = "none: a recording holds the frames as they were recorded";
      info.rawAdvice = "";
      break;
  }
  return info;
}

}  // namespace slicecap::rig
