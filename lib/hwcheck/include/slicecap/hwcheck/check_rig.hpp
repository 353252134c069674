// The running camera and the LED the hardware check drives, and the frames it has seen.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led.hpp"
#include "slicecap/hal/led_timeline.hpp"

namespace slicecap::hwcheck {

/// \brief A frame and when the application got it (on the same clock as the LED's switches).
struct SeenFrame {
  hal::Frame frame;
  std::int64_t arrivalUs = 0;
};

/// \brief The camera (configured and started by the caller) and the LED, with every LED switch
/// recorded on `clock` as it is commanded. Not thread-safe.
class CheckRig {
 public:
  CheckRig(hal::Camera& camera, hal::Led& led, hal::Clock& clock);

  hal::Camera& camera() { return camera_; }
  hal::Clock& clock() { return clock_; }
  /// \brief Switches the LED and records the command's time, which it returns. Throws what the
  /// LED throws.
  std::int64_t setLed(bool on);
  const hal::LedTimeline& switches() const { return *switches_; }
  bool ledOn() const { return ledOn_; }

  /// \brief The next frame, waiting at most `timeout`; nullopt on a timeout. Throws
  /// HardwareCheckError naming the camera when the stream ended or failed.
  std::optional<SeenFrame> next(std::chrono::milliseconds timeout);
  /// \brief Frames for `durationUs` of the clock (at least one; a timeout of a second without a
  /// frame throws HardwareCheckError naming the camera).
  std::vector<SeenFrame> collect(std::int64_t durationUs);
  /// \brief Camera::lockExposure, counted (frames say how many locks they were taken under).
  /// Throws what the camera throws.
  hal::ExposureLock lock(const hal::ExposureSetting& setting);
  /// \brief Locks `setting` and returns the first frame taken under that lock (its
  /// exposureLocks counts it), with the frames before it in `before` when given. Throws
  /// HardwareCheckError naming the camera when the lock is refused or no such frame comes
  /// within `maxFrames`.
  SeenFrame lockAndWait(const hal::ExposureSetting& setting, int maxFrames = 20,
                        std::vector<SeenFrame>* before = nullptr);
  std::uint32_t locksMade() const { return locks_; }

 private:
  hal::Camera& camera_;
  hal::Led& led_;
  hal::Clock& clock_;
  std::shared_ptr<hal::LedTimeline> switches_;
  bool ledOn_;
  std::uint32_t locks_ = 0;
};

}  // namespace slicecap::hwcheck
