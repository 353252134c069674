// The hardware check's camera loop and LED record.
#include "slicecap/hwcheck/check_rig.hpp"

#include <stdexcept>

#include "slicecap/hwcheck/hardware_check_error.hpp"

namespace slicecap::hwcheck {

CheckRig::CheckRig(hal::Camera& camera, hal::Led& led, hal::Clock& clock)
    : camera_(camera),
      led_(led),
      clock_(clock),
      switches_(std::make_shared<hal::LedTimeline>(led.isOn())),
      ledOn_(led.isOn()) {}

std::int64_t CheckRig::setLed(bool on) {
  // The time before the call: the GPIO write happens within the call, and the offset the LED
  // timing measures then includes the call's own duration, as the daemon's record does.
  const std::int64_t atUs = clock_.nowUs();
  led_.set(on);
  switches_->record(atUs, on);
  ledOn_ = on;
  return atUs;
}

std::optional<SeenFrame> CheckRig::next(std::chrono::milliseconds timeout) {
  hal::CaptureResult result = camera_.nextFrame(timeout);
  switch (result.status) {
    case hal::CaptureResult::Status::Frame:
      return SeenFrame{std::move(*result.frame), clock_.nowUs()};
    case hal::CaptureResult::Status::Timeout:
      return std::nullopt;
    case hal::CaptureResult::Status::EndOfStream:
      throw HardwareCheckError(camera_.id() + ": the camera's stream ended during the check");
    case hal::CaptureResult::Status::Error:
      break;
  }
  throw HardwareCheckError(camera_.id() + ": " + result.error);
}

std::vector<SeenFrame> CheckRig::collect(std::int64_t durationUs) {
  std::vector<SeenFrame> frames;
  const std::int64_t endUs = clock_.nowUs() + durationUs;
  while (frames.empty() || clock_.nowUs() < endUs) {
    std::optional<SeenFrame> seen = next(std::chrono::milliseconds(1000));
    if (!seen) {
      if (!frames.empty() && clock_.nowUs() >= endUs) break;
      throw HardwareCheckError(camera_.id() + ": no frame for a second");
    }
    frames.push_back(std::move(*seen));
  }
  return frames;
}

hal::ExposureLock CheckRig::lock(const hal::ExposureSetting& setting) {
  hal::ExposureLock result = camera_.lockExposure(setting);
  if (result.locked) ++locks_;
  return result;
}

SeenFrame CheckRig::lockAndWait(const hal::ExposureSetting& setting, int maxFrames,
                                std::vector<SeenFrame>* before) {
  const hal::ExposureLock locked = lock(setting);
  if (!locked.locked)
    throw HardwareCheckError(camera_.id() + " refused an exposure lock: " + locked.reason);
  for (int n = 0; n < maxFrames; ++n) {
    std::optional<SeenFrame> seen = next(std::chrono::milliseconds(1000));
    if (!seen) throw HardwareCheckError(camera_.id() + ": no frame for a second");
    if (seen->frame.metadata.exposureLocks >= locks_) return std::move(*seen);
    if (before) before->push_back(std::move(*seen));
  }
  throw HardwareCheckError(camera_.id() + ": no frame was taken under the exposure lock within " +
                           std::to_string(maxFrames) + " frames");
}

}  // namespace slicecap::hwcheck
