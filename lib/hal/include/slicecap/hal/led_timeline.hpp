// When the LED changed, on the clock the camera's timestamps use; an LED that keeps that record.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led_exposure.hpp"
#include "slicecap/hal/led.hpp"

namespace slicecap::hal {

/// \brief The LED's switches in time order on one clock. Thread-safe: a camera model reads it
/// from the frame loop while the LED is driven.
class LedTimeline {
 public:
  explicit LedTimeline(bool initiallyOn = false) : initiallyOn_(initiallyOn) {}
  /// \brief From `timeUs` on the LED is `on`. A switch to the state it already has is not kept.
  /// Throws HalError when `timeUs` is before the last switch recorded.
  void record(std::int64_t timeUs, bool on);
  bool stateAt(std::int64_t timeUs) const;
  /// \brief Microseconds of [startUs, endUs) with the LED on.
  double onTimeUs(double startUs, double endUs) const;
  /// \brief The LED over a frame's rows whose exposure spans [row0StartUs, row0StartUs +
  /// (heightPx - 1) * lineTimeUs + exposureUs).
  LedExposure exposureOf(std::int64_t row0StartUs, double lineTimeUs, double exposureUs,
                         int heightPx, double guardUs) const;
  /// \brief The first switch to `on` after `timeUs`, or nullopt.
  std::optional<std::int64_t> firstSwitchAfter(std::int64_t timeUs, bool on) const;
  /// \brief Drops switches before `timeUs` that no later query needs (keeps the state there).
  void forgetBefore(std::int64_t timeUs);
  std::size_t size() const;

 private:
  mutable std::mutex mutex_;
  bool initiallyOn_;
  std::vector<LedChange> changes_;
  bool stateAtLocked(std::int64_t timeUs) const;
};

/// \brief An LED that records every switch it makes on `timeline`, at the clock's time plus
/// `switchDelayUs` (a model of the light's own latency; 0 for the daemon's record of commands).
/// A switch the inner LED refused (threw) is not recorded.
class TimelineLed final : public Led {
 public:
  TimelineLed(std::unique_ptr<Led> inner, const Clock& clock,
              std::shared_ptr<LedTimeline> timeline, std::int64_t switchDelayUs = 0);
  std::string id() const override { return inner_->id(); }
  void set(bool on) override;
  bool isOn() const override { return inner_->isOn(); }
  const std::shared_ptr<LedTimeline>& timeline() const { return timeline_; }

 private:
  std::unique_ptr<Led> inner_;
  const Clock& clock_;
  std::shared_ptr<LedTimeline> timeline_;
  std::int64_t switchDelayUs_;
};

}  // namespace slicecap::hal
