// slicecapd.conf to the daemon's parts: the LED and strobe, the camera factory and pipelines, what
// a sweep keeps, and the session's tables.
#include "slicecap/rig/daemon_parts.hpp"

#include <memory>
#include <string>
#include <variant>

#include "configured_capture_rig.hpp"
#include "configured_outputs.hpp"
#include "method_tables.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/rig/configured_devices.hpp"
#include "slicecap/rig/device_description.hpp"

namespace slicecap::rig {
namespace {

using daemon::DaemonConfig;

// What the recordings say made them: the daemon, and which simulated camera.
std::string recordingsCreator(const DeviceDescription& devices) {
  std::string createdBy = std::string("slicecapd ") + kVersion;
  if (std::holds_alternative<ModelCameraDescription>(devices.camera)) createdBy += " (model camera)";
  if (std::holds_alternative<FileCameraDescription>(devices.camera)) createdBy += " (file camera)";
  return createdBy;
}

}  // namespace

daemon::DaemonParts daemonPartsFrom(const DaemonConfig& config, hal::Clock& clock,
                                    std::vector<std::string> warnings) {
  daemon::DaemonParts parts;
  parts.storage = config.storage;
  parts.clock = &clock;
  parts.warnings = std::move(warnings);
  // How the strobe drives the LED.
  parts.ledAlternate = config.ledAlternate;
  parts.hdrLevels = config.hdrLevels;
  parts.strobe.framesPerState = config.ledFramesPerState;
  parts.strobe.guardUs = config.ledGuardUs;
  parts.strobe.readoutUs = config.readoutUs;
  // What the sweeps read and keep: settings, read before the devices.
  const capture::PipelineSettings pipeline = pipelineSettingsFrom(config);
  const OutputSettings outputs = outputSettingsFrom(config);

  // The devices, described once and opened from the description. What the recordings will say
  // made them is the description's too: named before anything opens.
  const DeviceDescription devices = describeDevices(config);
  std::string createdBy = recordingsCreator(devices);
  // camera = model: the LED's light as the model camera sees it.
  auto modelLight = std::make_shared<hal::LedTimeline>();
  parts.led = openLed(devices.led, clock, modelLight);
  parts.cameraConfig = devices.cameraConfig;
  parts.decoding = devices.decoding;
  parts.refuseBrokenDecoding = config.refuseBrokenDecoding;
  CameraSources sources = makeCameraSources(devices, clock, modelLight, ModelScene::Sweep);
  parts.outputs =
      std::make_unique<ConfiguredSessionOutputs>(outputs, sources.rigFor, std::move(createdBy));
  parts.rig = std::make_unique<ConfiguredCaptureRig>(std::move(sources), pipeline);
  parts.tables = std::make_unique<MethodTables>();
  return parts;
}

}  // namespace slicecap::rig
