// systemd's sd-daemon calls, or stand-ins that find no systemd in a build without libsystemd.
#pragma once

// SLICECAP_HAS_SYSTEMD is set on the files that include this only (lib/daemon/CMakeLists.txt).
#if SLICECAP_HAS_SYSTEMD
#include <systemd/sd-daemon.h>
#else
#include <cstdint>

// Without libsystemd (-DSLICECAP_WITH_SYSTEMD=OFF) slicecapd runs as under no service manager:
// no socket passed (it binds its own), no watchdog, nobody to tell it is ready. The packaged
// unit (Type=notify, WatchdogSec=) needs a build with systemd (docs/guide/install.md).
#define SD_LISTEN_FDS_START 3  // as sd-daemon.h: the first descriptor systemd passes
inline int sd_listen_fds(int) { return 0; }
inline int sd_watchdog_enabled(int, std::uint64_t*) { return 0; }
inline int sd_notify(int, const char*) { return 0; }
#endif
