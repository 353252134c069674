// What the libgpiod 1.x and 2.x versions of GpiodLed share: the line object's interface and the
// wording of their errors, so both name chip and line the same way.
#pragma once

#include <cerrno>
#include <cstring>
#include <memory>
#include <string>

#include "slicecap/hal/gpiod_led.hpp"

namespace slicecap::hal {

/// \brief A requested output line; each libgpiod version implements it in its own file.
namespace detail {
class GpioOutputLine {
 public:
  virtual ~GpioOutputLine() = default;
  virtual void setActive(bool active) = 0;  ///< throws GpioError
  virtual std::string where() const = 0;    ///< "gpiochip0:17 (GPIO17)"
};

/// \brief Finds and requests the line; defined by the libgpiod version's source file.
std::unique_ptr<GpioOutputLine> openGpioOutputLine(const GpioLineSpec& spec);
}  // namespace detail

namespace gpiod_detail {

inline constexpr const char* kConsumer = "slicecapd";

inline std::string chipPath(const std::string& chip) {
  if (!chip.empty() && chip.front() == '/') return chip;
  return "/dev/" + chip;
}

inline std::string lineLabel(const GpioLineSpec& spec) {
  const std::string chip = spec.chip.empty() ? std::string("any chip") : spec.chip;
  return "GPIO line '" + spec.line + "' on " + chip;
}

[[noreturn]] inline void fail(const std::string& what, int errorNumber) {
  throw GpioError(what + ": " + std::strerror(errorNumber));
}

}  // namespace gpiod_detail
}  // namespace slicecap::hal
