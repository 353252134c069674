// The LED on the box: one GPIO output line through libgpiod (1.6 on Debian 12, 2.x behind the
// CMake option SLICECAP_GPIOD_V2), driving the LED's MOSFET or constant-current driver.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "slicecap/core/error.hpp"
#include "slicecap/hal/led.hpp"

namespace slicecap::hal {

namespace detail {
class GpioOutputLine;  // one per libgpiod version, in src/
}

/// \brief A GPIO line that cannot be found, requested or driven; what() names the chip and line
/// and says what the kernel answered (e.g. busy: in use by another program).
class GpioError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief Which line drives the LED, as slicecapd.conf gives it (led_chip, led_line,
/// led_active_low). `line` is a name (as `gpioinfo` lists it: "GPIO17", "SLICECAP_LED") or a
/// decimal offset on `chip`. `chip` is a name ("gpiochip0"), a path ("/dev/gpiochip0") or empty:
/// a named line is then looked up on every chip (the Pi 5 puts its header on another chip than
/// the Pi 4), and an offset needs a chip.
struct GpioLineSpec {
  std::string chip;
  std::string line = "GPIO17";
  bool activeLow = false;
};

/// \brief The line's offset when `line` is all decimal digits; nullopt for a name.
std::optional<unsigned> gpioLineOffset(const std::string& line);

/// \brief The LED on a GPIO output line, requested with the consumer name "slicecapd" so
/// `gpioinfo` shows who holds it. The line is requested already inactive (LED off) and driven
/// inactive again before it is released, so the LED is off whenever this object is gone.
class GpiodLed final : public Led {
 public:
  /// \brief Finds and requests the line. Throws GpioError naming chip and line: no such chip,
  /// no such line, or the request refused (busy, permission).
  explicit GpiodLed(const GpioLineSpec& spec);
  ~GpiodLed() override;
  GpiodLed(const GpiodLed&) = delete;
  GpiodLed& operator=(const GpiodLed&) = delete;

  /// \brief "gpiochip0:17 (GPIO17)": where the line was found.
  std::string id() const override;
  /// \brief Drives the line active (on) or inactive; GpioError if the kernel refuses.
  void set(bool on) override;
  bool isOn() const override { return on_; }

 private:
  std::unique_ptr<detail::GpioOutputLine> line_;
  bool on_ = false;
};

}  // namespace slicecap::hal
