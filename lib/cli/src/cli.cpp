// Subcommand dispatch, top-level help and the exception-to-exit-code boundary.
#include "slicecap/cli/cli.hpp"

#include <iostream>

#include "slicecap/cli/command.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/methods/errors.hpp"

namespace slicecap::cli {

std::vector<Command> allCommands() {
  return {reconstructCommand(), sampleCommand(),   compareCommand(),  generateCommand(),
          evalCommand(),        previewCommand(),  isotropyCommand(), priorTrainCommand(),
          targetCommand(),      simulateCommand(), sessionCommand(),  sweepCommand(),
          statusCommand(),      exportCommand(),   processCommand(),  captureOfflineCommand(),
          calibrateCommand(),   btfCommand(),       fitCommand()};
}

namespace {

void printTopLevelHelp(std::ostream& out, const std::vector<Command>& commands) {
  out << "slicecap " << kVersion
      << ": sparse anisotropic BRDF capture and reconstruction (Filip & Vavra 2013, Method B)\n\n"
      << "usage: slicecap COMMAND [ARGS...]    (slicecap COMMAND --help for "
         "details)\n\ncommands:\n";
  for (const Command& c : commands) {
    std::string first = c.spec.description.substr(0, c.spec.description.find('\n'));
    out << "  " << c.spec.name
        << std::string(c.spec.name.size() < 14 ? 14 - c.spec.name.size() : 1, ' ') << first << "\n";
  }
  out << "\nexit codes: 0 success, 1 failure (message on stderr), 2 bad usage\n";
}

}  // namespace

int runCli(std::span<const std::string> args, std::ostream& out, std::ostream& err) {
  const std::vector<Command> commands = allCommands();
  if (args.empty()) {
    printTopLevelHelp(err, commands);
    return kExitUsage;
  }
  if (args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    printTopLevelHelp(out, commands);
    return kExitOk;
  }
  if (args[0] == "--version") {
    out << "slicecap " << kVersion << "\n";
    return kExitOk;
  }
  for (const Command& command : commands) {
    if (command.spec.name != args[0]) continue;
    Streams streams{out, err};
    try {
      const ParsedArgs parsed = parseArgs(command.spec, args.subspan(1));
      if (parsed.helpRequested) {
        out << usageText(command.spec);
        return kExitOk;
      }
      return command.run(parsed, streams);
    } catch (const UsageError& e) {
      err << "slicecap: " << e.what() << "\n";
      return kExitUsage;
    } catch (const methods::MethodError& e) {
      // A method name or RBF spec from the command line: bad usage as the CLI's own checks.
      err << "slicecap: " << e.what() << "\n";
      return kExitUsage;
    } catch (const std::exception& e) {
      err << "slicecap " << command.spec.name << ": " << e.what() << "\n";
      return kExitFailure;
    }
  }
  err << "slicecap: unknown command '" << args[0] << "' (see slicecap --help)\n";
  return kExitUsage;
}

}  // namespace slicecap::cli
