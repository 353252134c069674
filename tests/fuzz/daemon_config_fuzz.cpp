// libFuzzer target: any bytes as slicecapd.conf. The parser returns a configuration or throws
// ConfigError naming the line; anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "slicecap/daemon/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    (void)slicecap::daemon::parseDaemonConfig(in, "fuzz.conf");
  } catch (const slicecap::daemon::ConfigError&) {
  }
  return 0;
}
