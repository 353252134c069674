// GpiodLed's parts that do not depend on the libgpiod version: the line spec and the LED state.
#include "gpiod_led_common.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace slicecap::hal {

std::optional<unsigned> gpioLineOffset(const std::string& line) {
  if (line.empty() || !std::all_of(line.begin(), line.end(),
                                   [](unsigned char c) { return std::isdigit(c) != 0; }))
    return std::nullopt;
  unsigned offset = 0;
  const auto [end, error] = std::from_chars(line.data(), line.data() + line.size(), offset);
  if (error != std::errc() || end != line.data() + line.size()) return std::nullopt;
  return offset;
}

GpiodLed::GpiodLed(const GpioLineSpec& spec) : line_(detail::openGpioOutputLine(spec)) {}

GpiodLed::~GpiodLed() {
  // The line object drives the line inactive before releasing it; this is the belt to those
  // braces, and must not throw from a destructor.
  try {
    if (line_) line_->setActive(false);
  } catch (const GpioError&) {
  }
}

std::string GpiodLed::id() const { return line_->where(); }

void GpiodLed::set(bool on) {
  line_->setActive(on);
  on_ = on;
}

}  // namespace slicecap::hal
