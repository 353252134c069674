// What a subcommand is: its spec (for parsing and --help) and its body.
#pragma once

#include <functional>
#include <iosfwd>
#include <vector>

#include "slicecap/cli/args.hpp"

namespace slicecap::cli {

/// \brief Where a command writes: results to `out`, progress and diagnostics to `err`.
struct Streams {
  std::ostream& out;
  std::ostream& err;
};

/// \brief A subcommand. `run` returns an exit code and may throw (UsageError -> 2, other -> 1).
struct Command {
  CommandSpec spec;
  std::function<int(const ParsedArgs&, Streams&)> run;
};

Command evalCommand();
Command previewCommand();
Command reconstructCommand();
Command sampleCommand();
Command compareCommand();
Command generateCommand();
Command sessionCommand();
Command sweepCommand();
Command statusCommand();
Command exportCommand();
Command targetCommand();
Command simulateCommand();
Command isotropyCommand();
Command priorTrainCommand();
Command processCommand();
Command captureOfflineCommand();
Command calibrateCommand();
Command btfCommand();
Command fitCommand();

/// \brief Every subcommand, in the order `slicecap --help` lists them.
std::vector<Command> allCommands();

}  // namespace slicecap::cli
