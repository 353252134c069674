// slicecapd's command line and start-up: configuration to devices, pipeline and reconstruction.
#pragma once

#include <iosfwd>
#include <span>
#include <string>

namespace slicecap::slicecapd {

/// \brief Runs slicecapd with its arguments (without the program name). Exit codes: 0 after a
/// normal stop (SIGTERM, SIGINT) or a finished one-shot mode (--print-config, --check-config,
/// --led-off), 1 on a start-up failure (the message names the file, device or line), 2 on bad
/// usage.
int run(std::span<const std::string> args, std::ostream& out, std::ostream& err);

}  // namespace slicecap::slicecapd
