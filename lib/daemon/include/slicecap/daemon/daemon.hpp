// slicecapd's core: one event loop serving the control socket, pumping camera frames through the
// capture pipeline into the session, strobing the LED, and talking to systemd.
#pragma once

#include <memory>
#include <vector>

#include "slicecap/daemon/daemon_parts.hpp"

namespace slicecap::daemon {

/// \brief The signals that stop the daemon cleanly (LED off, camera stopped): every signal whose
/// default action ends the process and that is not a fault of the process itself: SIGTERM
/// (systemd), SIGINT (a terminal), SIGHUP (a dropped SSH session), SIGQUIT, SIGUSR1, SIGUSR2,
/// SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGIO, SIGPWR, SIGSTKFLT and the real-time signals.
/// SIGPIPE and SIGXFSZ are not among them: the Daemon ignores them (a client that hangs up, a file
/// size limit: the write fails and says so). A program that makes a Daemon blocks them with
/// blockSignalsInThisAndLaterThreads before it opens a camera or starts any other thread.
std::vector<int> stopSignals();

/// \brief The daemon. The LED is on only while a sweep is capturing, and off when a sweep pauses
/// or stops, when the camera fails, when run() returns and in the destructor.
class Daemon {
 public:
  /// \brief Takes the listening socket (socket-activated or bound by the caller), switches the
  /// LED off and ignores SIGPIPE and SIGXFSZ in the whole process. Throws io::IoError if the
  /// storage cannot be used; std::logic_error if `parts` lacks its rig, tables or LED (a bug of
  /// the caller's).
  Daemon(DaemonParts parts, int listenFd);
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  /// \brief Serves until one of stopSignals() (or stop()); tells systemd READY=1 first and pings
  /// its watchdog at half the interval when it asks for one.
  void run();
  /// \brief Thread-safe: makes run() return.
  void stop();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::daemon
