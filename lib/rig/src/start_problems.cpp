// What `slicecapd --check-config` finds wrong before a start opens any device.
#include <grp.h>

#include <filesystem>
#include <functional>
#include <optional>

#include "slicecap/daemon/control_server.hpp"
#include "slicecap/hal/rpi_tuning.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/rig/configured_devices.hpp"
#include "slicecap/rig/daemon_parts.hpp"
#include "slicecap/sim/material.hpp"

namespace slicecap::rig {

namespace fs = std::filesystem;
using daemon::DaemonConfig;

// --check-config opens no device, so a camera or GPIO line is not tried.
std::vector<std::string> startProblems(const DaemonConfig& config) {
  std::vector<std::string> problems;
  const auto check = [&problems](const std::function<void()>& what) {
    try {
      what();
    } catch (const std::exception& error) {
      problems.emplace_back(error.what());
    }
  };
  for (std::string& missing : backendsNotBuilt(config)) problems.push_back(std::move(missing));
  if (const auto problem = daemon::socketPathProblem(config.socket))
    problems.push_back("socket: " + *problem);
  if (!config.socketGroup.empty() && !::getgrnam(config.socketGroup.c_str()))
    problems.push_back("socket_group: group " + config.socketGroup +
                       " does not exist (add it, e.g. with systemd-sysusers and the package's "
                       "slicecap.sysusers, or leave socket_group empty)");
  if (config.camera == DaemonConfig::CameraKind::File)
    check([&] { findRecordings(config.recording); });
  if (config.camera == DaemonConfig::CameraKind::Model)
    check([&] { sim::loadMaterial(config.modelMaterial); });
  if (config.target != "default") check([&] { io::readTargetJson(config.target); });
  if (!config.calibration.empty())
    check([&] {
      io::cameraFromJson(io::readJsonFile(config.calibration), config.calibration.string(), "");
    });
  // A named tuning file is checked whatever the camera: bad input is said, not kept for later.
  if (config.tuningFile.kind == hal::TuningFileSetting::Kind::Path)
    check([&] { hal::validateTuningFile(config.tuningFile.path, std::nullopt); });
  std::error_code error;
  if (fs::exists(config.storage, error) && !fs::is_directory(config.storage, error))
    problems.push_back("storage: " + config.storage.string() + " is not a folder");
  return problems;
}

}  // namespace slicecap::rig
