// The `slicecap` command line: subcommands, their help, and exit codes (0 ok, 1 failure, 2 usage).
#pragma once

#include <iosfwd>
#include <span>
#include <string>

namespace slicecap::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

/// \brief Runs `slicecap ARGS...` (args without the program name), writing results to `out` and
/// messages to `err`. Never throws: errors become a message on `err` and an exit code.
int runCli(std::span<const std::string> args, std::ostream& out, std::ostream& err);

}  // namespace slicecap::cli
