// The control client's names in the daemon's namespace (its tests drive the daemon through it).
#pragma once

#include "slicecap/control/control_client.hpp"
#include "slicecap/daemon/protocol.hpp"

namespace slicecap::daemon {

using control::ConnectionError;
using control::ControlClient;
using control::DaemonError;

}  // namespace slicecap::daemon
