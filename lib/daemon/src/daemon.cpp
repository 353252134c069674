// slicecapd's event loop and what runs on it: the control server answering requests
// (daemon_replies.cpp), the sweep's devices (sweep_devices.cpp), systemd's readiness and watchdog.
#include "slicecap/daemon/daemon.hpp"

#include <signal.h>
#include "sd_daemon.hpp"

#include <csignal>
#include <iostream>
#include <stdexcept>

#include "daemon_replies.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "sweep_devices.hpp"

namespace slicecap::daemon {

std::vector<int> stopSignals() {
  std::vector<int> signals{SIGTERM,   SIGINT,  SIGHUP,  SIGQUIT, SIGUSR1, SIGUSR2,  SIGALRM,
                           SIGVTALRM, SIGPROF, SIGXCPU, SIGIO,   SIGPWR,  SIGSTKFLT};
  // SIGRTMIN, not 32: the C library keeps the first real-time signals for its threads.
  for (int s = SIGRTMIN; s <= SIGRTMAX; ++s)
    signals.push_back(s);
  return signals;
}

namespace {

// The parts as the devices use them: every switch of the LED recorded on `commanded`, on the
// camera's clock (the strobe labels frames from it), and the strobe alternating as configured.
DaemonParts withRecordedSwitches(DaemonParts parts, hal::Clock& clock,
                                 const std::shared_ptr<hal::LedTimeline>& commanded) {
  parts.strobe.alternate = parts.ledAlternate;
  parts.led = std::make_unique<hal::TimelineLed>(std::move(parts.led), clock, commanded);
  return parts;
}

// The session manager with the rig's tables; a computation the tables do not offer is left out.
SessionManager managerOf(const DaemonParts& parts) {
  SessionTables& tables = *parts.tables;
  PreviewFunction preview;
  if (tables.writesPreviews())
    preview = [&tables](const Abrdf& table, const std::filesystem::path& png) {
      tables.preview(table, png);
    };
  IsotropyFunction isotropy;
  if (tables.testsIsotropy())
    isotropy = [&tables](const SliceSet& slices) { return tables.isotropy(slices); };
  MaterialFunction material;
  if (tables.fitsMaterial())
    material = [&tables](const Abrdf& table, const std::string& name) {
      return tables.material(table, name);
    };
  return SessionManager(
      parts.storage,
      [&tables](const SliceSet& slices, const std::string& method) {
        return tables.reconstruct(slices, method);
      },
      std::move(preview), std::move(isotropy), std::move(material));
}

}  // namespace

struct Daemon::State {
  hal::SteadyClock steadyClock;
  // Every switch the daemon makes, on the camera's clock: the strobe labels frames from it.
  std::shared_ptr<hal::LedTimeline> commanded = std::make_shared<hal::LedTimeline>();
  hal::Clock& clock;
  DaemonParts parts;
  EventLoop loop{stopSignals()};
  SessionManager manager;
  SweepDevices devices;
  std::unique_ptr<ControlServer> server;

  explicit State(DaemonParts p)
      : clock(p.clock ? *p.clock : steadyClock),
        parts(withRecordedSwitches(std::move(p), clock, commanded)),
        manager(managerOf(parts)),
        devices(parts, loop, manager, clock, commanded) {}
};

Daemon::Daemon(DaemonParts parts, int listenFd) {
  if (!parts.rig || !parts.tables || !parts.led)
    throw std::logic_error("DaemonParts without a rig, tables or LED");
  state_ = std::make_unique<State>(std::move(parts));
  // A client that hangs up while a write is on its way must never end the daemon (the control
  // socket sends with MSG_NOSIGNAL; this covers every other write, and a `kill -PIPE`); a file
  // size limit fails the write with EFBIG, which the storage reports, instead of killing it.
  std::signal(SIGPIPE, SIG_IGN);
  std::signal(SIGXFSZ, SIG_IGN);
  state_->devices.ledOff();
  state_->server = std::make_unique<ControlServer>(
      state_->loop, listenFd,
      [this](const control::Request& request) {
        return answer(request, state_->manager, state_->devices, state_->parts.storage);
      },
      state_->parts.clientLimits);
}

Daemon::~Daemon() {
  state_->devices.stopCamera();
}

void Daemon::run() {
  state_->loop.onSignal([this](int signalNumber) {
    const char* name = sigabbrev_np(signalNumber);  // none for the real-time signals
    std::cerr << "slicecapd: stopping on "
              << (name ? "SIG" + std::string(name) : "signal " + std::to_string(signalNumber))
              << "\n";
    state_->loop.stop();
  });
  std::uint64_t watchdogUs = 0;
  if (sd_watchdog_enabled(0, &watchdogUs) > 0 && watchdogUs > 0) {
    state_->loop.addTimer(std::chrono::microseconds(watchdogUs / 2), true,
                          [] { sd_notify(0, "WATCHDOG=1"); });
  }
  // A restarted daemon may come back to a paused sweep; nothing captures until a person says so.
  state_->devices.reconcile();
  sd_notify(0, "READY=1");
  try {
    state_->loop.run();
  } catch (...) {
    state_->devices.stopCamera();
    throw;
  }
  sd_notify(0, "STOPPING=1");
  state_->devices.stopCamera();
}

void Daemon::stop() {
  state_->loop.stop();
}

}  // namespace slicecap::daemon
