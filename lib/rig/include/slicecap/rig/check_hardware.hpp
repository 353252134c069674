// `slicecapd --check-hardware`: opens the configured camera and LED as the daemon would and
// prints (or writes) what lib/hwcheck measures.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

#include "slicecap/daemon/config.hpp"
#include "slicecap/hwcheck/hardware_check.hpp"

namespace slicecap::rig {

struct CheckHardwareOptions {
  double seconds = 2.0;                    ///< --seconds: the frame timing's capture
  std::optional<std::string> writeConfig;  ///< --write-config FILE
  bool overwrite = false;                  ///< --overwrite: replace an existing FILE
  bool json = false;                       ///< --json
};

/// \brief What the configured camera backend offers (its cameras' modes) and what the RAW
/// setting will do with the camera the sweep opens, for the report's camera and RAW items.
hwcheck::BackendInfo describeBackend(const daemon::DaemonConfig& config);

/// \brief Runs the check. Returns 0 when every item is ok or warn, 1 when an item failed (the
/// report says which and what to do), the daemon is running, or the configuration could not
/// be written (the message names the file).
int checkHardware(const daemon::DaemonConfig& config, const CheckHardwareOptions& options,
                  std::ostream& out, std::ostream& err);

}  // namespace slicecap::rig
