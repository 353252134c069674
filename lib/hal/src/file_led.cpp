// The LED log: one line per change, flushed as it happens.
#include "slicecap/hal/file_led.hpp"

#include <fstream>
#include <sstream>
#include <string>

namespace slicecap::hal {

FileLed::FileLed(std::filesystem::path log, Clock& clock) : path_(std::move(log)), clock_(clock) {
  file_ = std::fopen(path_.c_str(), "a");
  if (!file_) throw DeviceError(path_.string() + ": cannot open the LED log");
  write(false);
}

FileLed::~FileLed() {
  try {
    if (on_) write(false);
  } catch (...) {  // a destructor must not throw; the log write is best effort here
  }
  std::fclose(file_);
}

void FileLed::set(bool on) {
  if (on != on_) write(on);
}

void FileLed::write(bool on) {
  if (std::fprintf(file_, "%lld %s\n", static_cast<long long>(clock_.nowUs()), on ? "on" : "off") <
          0 ||
      std::fflush(file_) != 0)
    throw DeviceError(path_.string() + ": cannot write the LED log");
  on_ = on;
}

std::vector<LedEvent> readLedLog(const std::filesystem::path& log) {
  std::ifstream in(log);
  if (!in) throw DeviceError(log.string() + ": cannot open the LED log");
  std::vector<LedEvent> events;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    long long timestamp = 0;
    std::string state, extra;
    if (!(fields >> timestamp >> state) || (state != "on" && state != "off") || (fields >> extra))
      throw DeviceError(log.string() + ":" + std::to_string(number) +
                        ": expected 'TIMESTAMP_US on|off', got '" + line + "'");
    events.push_back({timestamp, state == "on"});
  }
  return events;
}

}  // namespace slicecap::hal
