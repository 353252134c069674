// Sets LIBCAMERA_RPI_TUNING_FILE for the processed path before the daemon's camera opens.
#include "slicecap/rig/rpi_tuning_setup.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/device_backends.hpp"
#include "slicecap/hal/rpi_tuning.hpp"

namespace slicecap::rig {

using daemon::DaemonConfig;

namespace {

constexpr const char* kTuningVariable = "LIBCAMERA_RPI_TUNING_FILE";

/// The board's ISP from its device tree; nullopt off a Raspberry Pi (or without a device tree).
std::optional<hal::PiIsp> boardIsp() {
  std::ifstream in("/proc/device-tree/compatible", std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return hal::piIspOfCompatible(text.str());
}

std::string settingText(const hal::TuningFileSetting& setting) {
  switch (setting.kind) {
    case hal::TuningFileSetting::Kind::Auto: return "auto";
    case hal::TuningFileSetting::Kind::Off: return "off";
    case hal::TuningFileSetting::Kind::Path: return setting.path.string();
  }
  return "auto";
}

}  // namespace

std::optional<control::TuningFileView> applyRpiTuningFile(const DaemonConfig& config) {
  const hal::TuningFileSetting& setting = config.tuningFile;
  const auto chosen = [&](std::optional<std::string> file, std::string reason) {
    return control::TuningFileView{settingText(setting), std::move(file), std::move(reason)};
  };
  const std::optional<hal::PiIsp> isp = boardIsp();
  // A file named in the configuration is checked whether or not this camera will use it.
  if (setting.kind == hal::TuningFileSetting::Kind::Path) hal::validateTuningFile(setting.path, isp);
  if (config.camera != DaemonConfig::CameraKind::Libcamera) return std::nullopt;
  if (setting.kind == hal::TuningFileSetting::Kind::Off)
    return chosen(std::nullopt, "tuning_file = off: the camera's own tuning");
  if (const char* already = std::getenv(kTuningVariable); already && *already)
    return chosen(already, std::string("tuning_file: ") + kTuningVariable + " is already set (" +
                               already + ") and is left as it is");
  if (!isp && setting.kind == hal::TuningFileSetting::Kind::Auto)
    return chosen(std::nullopt, "tuning_file = auto: not a Raspberry Pi, the camera's own tuning");

  hal::TuningInputs inputs;
  inputs.raw = config.cameraRaw;
  inputs.isp = isp;
  inputs.tuningDir = hal::slicecapTuningDir();
  // The probe's manager is gone when this returns: the daemon's camera starts a new one, which
  // reads the variable (two managers alive at once abort the process).
  const std::vector<hal::CameraModes> cameras =
      hal::libcameraModes(config.widthPx, config.heightPx);
  if (const hal::CameraModes* camera = hal::findLibcameraCamera(cameras, config.cameraDevice)) {
    inputs.sensorModel = camera->sensorModel;
    inputs.rawGranted = camera->validatedRaw && !camera->validatedRaw->format.empty();
  }
  const hal::TuningChoice choice = hal::chooseTuningFile(setting, inputs);
  if (choice.file) {
    hal::validateTuningFile(*choice.file, isp);
    ::setenv(kTuningVariable, choice.file->c_str(), 1);
  }
  return chosen(choice.file ? std::optional<std::string>(choice.file->string()) : std::nullopt,
                choice.reason);
}

}  // namespace slicecap::rig
