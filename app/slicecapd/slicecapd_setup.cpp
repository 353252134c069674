// slicecapd's command line: parse it, read the configuration, and start the daemon with the parts
// lib/rig builds from it (or run a one-shot mode).
#include "slicecapd_setup.hpp"


#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "slicecap/core/error.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/daemon/config.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/daemon.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/rig/check_hardware.hpp"
#include "slicecap/rig/configured_devices.hpp"
#include "slicecap/rig/daemon_parts.hpp"
#include "slicecap/rig/device_description.hpp"
#include "slicecap/rig/rpi_tuning_setup.hpp"

namespace slicecap::slicecapd {
namespace {

namespace fs = std::filesystem;
using daemon::DaemonConfig;

constexpr const char* kUsage =
    "usage: slicecapd [--config FILE] [--print-config | --check-config | --led-off]\n"
    "       slicecapd [--config FILE] --check-hardware [--seconds N] [--write-config FILE\n"
    "                 [--overwrite]] [--json]\n"
    "  --config FILE    the configuration (default /etc/slicecap/slicecapd.conf)\n"
    "  --print-config   print the default configuration, every key documented, and exit\n"
    "  --check-config   read and check the configuration, open nothing, and exit\n"
    "  --led-off        switch the LED off and exit (the service's ExecStopPost)\n"
    "  --check-hardware measure the camera and LED with the target under the camera and print\n"
    "                   a report and the configuration lines it supports (the daemon must be\n"
    "                   stopped); --seconds N of frame timing (default 2), --write-config FILE\n"
    "                   writes the lines (an existing FILE only with --overwrite), --json\n"
    "  --version        print the version and exit\n";

struct Options {
  fs::path config = "/etc/slicecap/slicecapd.conf";
  bool printConfig = false, checkConfig = false, ledOff = false, version = false, help = false;
  bool checkHardware = false;
  rig::CheckHardwareOptions hardware;
};

Options parseOptions(std::span<const std::string> args) {
  Options options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--config") {
      if (i + 1 >= args.size()) throw UsageError("--config needs a FILE");
      options.config = args[++i];
    } else if (arg == "--print-config") {
      options.printConfig = true;
    } else if (arg == "--check-config") {
      options.checkConfig = true;
    } else if (arg == "--led-off") {
      options.ledOff = true;
    } else if (arg == "--check-hardware") {
      options.checkHardware = true;
    } else if (arg == "--seconds") {
      if (i + 1 >= args.size()) throw UsageError("--seconds needs a number");
      char* end = nullptr;
      const std::string& value = args[++i];
      options.hardware.seconds = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || !(options.hardware.seconds >= 0.2 && options.hardware.seconds <= 60))
        throw UsageError("--seconds '" + value + "' is not a number of seconds in 0.2..60");
    } else if (arg == "--write-config") {
      if (i + 1 >= args.size()) throw UsageError("--write-config needs a FILE");
      options.hardware.writeConfig = args[++i];
    } else if (arg == "--overwrite") {
      options.hardware.overwrite = true;
    } else if (arg == "--json") {
      options.hardware.json = true;
    } else if (arg == "--version") {
      options.version = true;
    } else if (arg == "--help" || arg == "-h") {
      options.help = true;
    } else {
      throw UsageError("unknown argument '" + arg + "'");
    }
  }
  const bool hardwareOnly = options.hardware.writeConfig || options.hardware.overwrite ||
                            options.hardware.json || options.hardware.seconds != 2.0;
  if (hardwareOnly && !options.checkHardware)
    throw UsageError("--seconds, --write-config, --overwrite and --json go with --check-hardware");
  if (options.hardware.overwrite && !options.hardware.writeConfig)
    throw UsageError("--overwrite goes with --write-config FILE");
  return options;
}

// `warnings`: configWarnings(config), already logged; every status shows them.
int serve(const DaemonConfig& config, std::vector<std::string> warnings, std::ostream& err) {
  // Before the camera: libcamera starts its threads in the camera's constructor, and a SIGTERM
  // that reached one of them would end the process without stopping the sweep cleanly.
  daemon::blockSignalsInThisAndLaterThreads(daemon::stopSignals());
  // Before the camera opens: libcamera reads the tuning file when its camera manager starts.
  const std::optional<control::TuningFileView> tuning = rig::applyRpiTuningFile(config);
  if (tuning) err << "slicecapd: " << tuning->reason << "\n";
  static hal::SteadyClock clock;  // the cameras' clock: it outlives them
  daemon::DaemonParts parts = rig::daemonPartsFrom(config, clock, std::move(warnings));
  parts.tuningFile = tuning;

  // Outlives the daemon: its socket file is removed when the daemon has stopped (not systemd's).
  const daemon::ListenSocket listening(
      {config.socket, 0660,
       config.socketGroup.empty() ? std::nullopt : std::optional<std::string>(config.socketGroup)});
  parts.clientLimits.idleTimeout = std::chrono::seconds(config.clientIdleTimeoutS);
  parts.clientLimits.socketGroup = listening.group();
  daemon::Daemon daemon(std::move(parts), listening.fd());
  err << "slicecapd " << kVersion << ": serving "
      << (listening.fromSystemd() ? std::string("the socket systemd passed")
                                  : config.socket.string())
      << ", sessions in " << config.storage.string() << "\n";
  daemon.run();
  return 0;
}

}  // namespace

int run(std::span<const std::string> args, std::ostream& out, std::ostream& err) {
  Options options;
  try {
    options = parseOptions(args);
  } catch (const UsageError& error) {
    err << "slicecapd: " << error.what() << "\n" << kUsage;
    return 2;
  }
  if (options.help) {
    out << kUsage;
    return 0;
  }
  if (options.version) {
    out << "slicecapd " << kVersion << "\n";
    return 0;
  }
  if (options.printConfig) {
    out << DaemonConfig::documentedDefaults();
    return 0;
  }
  try {
    const DaemonConfig config = daemon::readDaemonConfig(options.config);
    std::vector<std::string> warnings = daemon::configWarnings(config);
    for (const std::string& warning : warnings)
      err << "slicecapd: " << options.config.string() << ": warning: " << warning << "\n";
    if (options.checkConfig) {
      const std::vector<std::string> problems = rig::startProblems(config);
      for (const std::string& problem : problems)
        err << "slicecapd: " << options.config.string() << ": " << problem << "\n";
      if (!problems.empty()) return 1;
      out << options.config.string() << ": ok\n";
      return 0;
    }
    if (options.checkHardware) return rig::checkHardware(config, options.hardware, out, err);
    if (options.ledOff) {
      hal::SteadyClock clock;
      rig::openLed(rig::describeLed(config), clock)->set(false);
      return 0;
    }
    return serve(config, std::move(warnings), err);
  } catch (const std::exception& error) {
    err << "slicecapd: " << error.what() << "\n";
    return 1;
  }
}

}  // namespace slicecap::slicecapd
