// An LED that writes every change, with its time, to a log file (tests, offline runs).
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "slicecap/core/error.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led.hpp"

namespace slicecap::hal {

/// \brief A device or log that failed; what() names it.
class DeviceError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief Appends "TIMESTAMP_US on|off" lines to a log: "off" when opened (the LED's safe state),
/// then one line per change, flushed at once; the destructor turns the LED off.
class FileLed final : public Led {
 public:
  /// \brief Opens (appends to) the log; throws DeviceError naming it when it cannot.
  FileLed(std::filesystem::path log, Clock& clock);
  ~FileLed() override;
  FileLed(const FileLed&) = delete;
  FileLed& operator=(const FileLed&) = delete;

  std::string id() const override { return "file:" + path_.string(); }
  void set(bool on) override;
  bool isOn() const override { return on_; }

 private:
  void write(bool on);
  std::filesystem::path path_;
  Clock& clock_;
  std::FILE* file_ = nullptr;
  bool on_ = false;
};

/// \brief One line of an LED log.
struct LedEvent {
  std::int64_t timestampUs = 0;
  bool on = false;
  friend bool operator==(const LedEvent&, const LedEvent&) = default;
};

/// \brief Reads an LED log; throws DeviceError "PATH:LINE: problem" for a malformed line.
std::vector<LedEvent> readLedLog(const std::filesystem::path& log);

}  // namespace slicecap::hal
