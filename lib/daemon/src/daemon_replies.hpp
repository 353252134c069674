// The daemon's replies: each control request carried out by the session manager, with what the
// sweep's devices add (the status's device parts, the stop's recording) and must do (a redo's
// discarded texture, the devices following the new session state).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "slicecap/control/protocol.hpp"
#include "slicecap/daemon/session_manager.hpp"
#include "sweep_devices.hpp"

namespace slicecap::daemon {

/// \brief The reply to `request` (a ControlServer handler): its result, or a thrown RequestError
/// with the refusal's code and message. The devices follow the session state either way.
nlohmann::json answer(const control::Request& request, SessionManager& manager, SweepDevices& devices,
                      const std::filesystem::path& storage);

}  // namespace slicecap::daemon
