// The LED interface: libgpiod on the box (issue 6), a log file in tests and offline runs.
#pragma once

#include <string>

namespace slicecap::hal {

/// \brief The light. Safety: an implementation turns the LED off in its destructor, so it is off
/// on every exit path that unwinds; the daemon's unit file covers crashes.
class Led {
 public:
  virtual ~Led() = default;
  virtual std::string id() const = 0;
  /// \brief Switches the LED; strobing in step with frames is the caller's loop (one set() per
  /// frame). Throws std::runtime_error (naming the line or file) when the device fails.
  virtual void set(bool on) = 0;
  virtual bool isOn() const = 0;
};

}  // namespace slicecap::hal
