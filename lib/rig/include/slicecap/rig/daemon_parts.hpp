// slicecapd.conf to what the daemon runs with: its collaborators (CaptureRig, SessionOutputs,
// SessionTables, implemented in this module over hal, sim, capture, btf, methods, prior, render
// and material_export), its LED and its settings.
#pragma once

#include <string>
#include <vector>

#include "slicecap/daemon/config.hpp"
#include "slicecap/daemon/daemon_parts.hpp"
#include "slicecap/hal/clock.hpp"

namespace slicecap::rig {

/// \brief The daemon's parts from `config`, every device and file it names opened here, so a
/// mistake stops the start with a message before systemd hears READY. `clock` (the camera's) must
/// outlive the parts. `warnings`: configWarnings(config), which every status shows. The caller
/// sets clientLimits once it has the socket. Throws what opening a device or file throws, naming
/// it (hal::DeviceError, io::IoError, ...).
daemon::DaemonParts daemonPartsFrom(const daemon::DaemonConfig& config, hal::Clock& clock,
                                    std::vector<std::string> warnings);

/// \brief What a start would find wrong before it opens a device (`slicecapd --check-config`):
/// backends not built, the socket's path and group, and every file the configuration names, one
/// line each; empty when none. Opens no camera and no GPIO line.
std::vector<std::string> startProblems(const daemon::DaemonConfig& config);

}  // namespace slicecap::rig
