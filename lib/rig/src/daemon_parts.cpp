// slicecapd.conf to the daemon's parts: the LED and strobe, the camera factory and pipelines, what
// a sweep keeps, and the session's tables.
#include "slicecap/rig/daemon_parts.hpp"

#include "configured_capture_rig.hpp"
#include "configured_outputs.hpp"
#include "method_tables.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/rig/configured_devices.hpp"

namespace slicecap::rig {
namespace {

using daemon::DaemonConfig;

// The LED and how the strobe drives it, and what the camera is asked for.
void setLedAndCamera(daemon::DaemonParts& parts, const DaemonConfig& config, hal::Clock& clock,
                     const std::shared_ptr<hal::LedTimeline>& modelLight) {
  parts.led = openLed(config, clock, modelLight);
  parts.ledAlternate = config.ledAlternate;
  parts.hdrLevels = config.hdrLevels;
  parts.strobe.framesPerState = config.ledFramesPerState;
  parts.strobe.guardUs = config.ledGuardUs;
  parts.strobe.readoutUs = config.readoutUs;
  parts.cameraConfig = cameraConfigFrom(config);
}

// What the recordings say made them: the daemon, and which simulated camera.
std::string recordingsCreator(const DaemonConfig& config, const CameraSources& sources) {
  std::string createdBy = std::string("slicecapd ") + kVersion;
  if (config.camera == DaemonConfig::CameraKind::Model ||
      config.camera == DaemonConfig::CameraKind::File)
    createdBy += " (" + sources.kind + ")";
  return createdBy;
}

}  // namespace

daemon::DaemonParts daemonPartsFrom(const DaemonConfig& config, hal::Clock& clock,
                                    std::vector<std::string> warnings) {
  daemon::DaemonParts parts;
  parts.storage = config.storage;
  parts.clock = &clock;
  // camera = model: the LED's light as the model camera sees it.
  auto modelLight = std::make_shared<hal::LedTimeline>();
  setLedAndCamera(parts, config, clock, modelLight);
  parts.warnings = std::move(warnings);
  parts.decoding = daemon::decodingModeFromString(config.decoding);
  parts.refuseBrokenDecoding = config.refuseBrokenDecoding;

  const Rig configured = configuredRig(config);
  CameraSources sources = makeCameraSources(config, clock, modelLight, configured.target,
                                            configured.camera, ModelScene::Sweep);
  parts.outputs = std::make_unique<ConfiguredSessionOutputs>(config, sources.rigFor,
                                                             recordingsCreator(config, sources));
  parts.rig = std::make_unique<ConfiguredCaptureRig>(std::move(sources), pipelineSettingsFrom(config));
  parts.tables = std::make_unique<MethodTables>();
  return parts;
}

}  // namespace slicecap::rig
