// libFuzzer target: any bytes as a control request line. parseRequest must never throw or crash,
// and what it accepts must survive a round trip through encodeRequest.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "slicecap/control/protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace control = slicecap::control;
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  const auto parsed = control::parseRequest(line);
  if (const auto* request = std::get_if<control::Request>(&parsed)) {
    const auto again = control::parseRequest(control::encodeRequest(*request));
    const auto* reparsed = std::get_if<control::Request>(&again);
    if (reparsed == nullptr || reparsed->id != request->id ||
        control::commandName(reparsed->command) != control::commandName(request->command))
      std::abort();
  } else {
    (void)control::encodeError(std::get<control::ProtocolError>(parsed));
  }
  return 0;
}
