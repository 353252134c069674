// Time as the session sees it: the steady clock on the box, a fake clock in tests.
#pragma once

#include <cstdint>

namespace slicecap::hal {

/// \brief Microseconds on a monotonic time line (the same one camera timestamps use on the box).
class Clock {
 public:
  virtual ~Clock() = default;
  virtual std::int64_t nowUs() const = 0;
  /// \brief Returns once nowUs() >= timeUs (at once when it already is).
  virtual void sleepUntilUs(std::int64_t timeUs) = 0;
};

/// \brief std::chrono::steady_clock (CLOCK_MONOTONIC on Linux, as libcamera's timestamps).
class SteadyClock final : public Clock {
 public:
  std::int64_t nowUs() const override;
  void sleepUntilUs(std::int64_t timeUs) override;
};

/// \brief A clock that moves only when told: sleepUntilUs jumps to the time at once, so tests of
/// paced playback and timeouts run instantly and deterministically.
class FakeClock final : public Clock {
 public:
  explicit FakeClock(std::int64_t startUs = 0) : nowUs_(startUs) {}
  std::int64_t nowUs() const override { return nowUs_; }
  void sleepUntilUs(std::int64_t timeUs) override {
    if (timeUs > nowUs_) nowUs_ = timeUs;
  }
  void advanceUs(std::int64_t deltaUs) { nowUs_ += deltaUs; }

 private:
  std::int64_t nowUs_;
};

}  // namespace slicecap::hal
