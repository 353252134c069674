// libFuzzer target: any bytes as a control request line. parseRequest must never throw or crash,
// and what it accepts must survive a round trip through encodeRequest.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "slicecap/daemon/protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slicecap::daemon;
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  const auto parsed = parseRequest(line);
  if (const auto* request = std::get_if<Request>(&parsed)) {
    const auto again = parseRequest(encodeRequest(*request));
    const auto* reparsed = std::get_if<Request>(&again);
    if (reparsed == nullptr || reparsed->id != request->id ||
        commandName(reparsed->command) != commandName(request->command))
      std::abort();
  } else {
    (void)encodeError(std::get<ProtocolError>(parsed));
  }
  return 0;
}
