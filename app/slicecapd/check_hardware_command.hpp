// `slicecapd --check-hardware`: opens the configured camera and LED as the daemon would and
// prints (or writes) what lib/hwcheck measures.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

#include "slicecap/daemon/config.hpp"

namespace slicecap::slicecapd {

struct CheckHardwareOptions {
  double seconds = 2.0;                    ///< --seconds: the frame timing's capture
  std::optional<std::string> writeConfig;  ///< --write-config FILE
  bool overwrite = false;                  ///< --overwrite: replace an existing FILE
  bool json = false;                       ///< --json
};

/// \brief Runs the check. Returns 0 when every item is ok or warn, 1 when an item failed (the
/// report says which and what to do), the daemon is running, or the configuration could not
/// be written (the message names the file).
int checkHardware(const daemon::DaemonConfig& config, const CheckHardwareOptions& options,
                  std::ostream& out, std::ostream& err);

}  // namespace slicecap::slicecapd
