// The pinned frame duration's decisions: what FrameDurationLimits carries, how an exposure is
// kept inside the frame, and V4L2's frame interval and power-line-frequency menu value.
#include "slicecap/hal/frame_timing.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "slicecap/hal/camera_error.hpp"

namespace slicecap::hal {

namespace {

std::string microseconds(double us) {
  const double rounded = std::round(us * 10.0) / 10.0;
  std::string text = std::to_string(rounded);
  text.erase(text.find_last_not_of('0') + 1);
  if (text.back() == '.') text.pop_back();
  return text + " us";
}

}  // namespace

FrameDurationPlan planFrameDuration(std::optional<double> wantedUs,
                                    std::optional<FrameDurationRange> listed) {
  FrameDurationPlan plan;
  if (!wantedUs) return plan;
  if (!listed) {
    plan.notes.push_back("frame duration " + microseconds(*wantedUs) +
                         " not pinned: the camera lists no FrameDurationLimits control, its "
                         "frames keep its own duration");
    return plan;
  }
  const auto rounded = static_cast<std::int64_t>(std::llround(*wantedUs));
  const std::int64_t granted = std::clamp(rounded, listed->minUs, std::max(listed->minUs, listed->maxUs));
  if (granted != rounded)
    plan.notes.push_back("frame duration " + microseconds(*wantedUs) + " -> " +
                         microseconds(double(granted)) + " (the sensor mode's range " +
                         std::to_string(listed->minUs) + ".." + std::to_string(listed->maxUs) +
                         " us)");
  plan.limitsUs = granted;
  plan.grantedUs = double(granted);
  return plan;
}

ExposureInFrame clampExposureToFrame(double exposureUs, std::optional<double> frameDurationUs) {
  if (!frameDurationUs || exposureUs <= *frameDurationUs) return {exposureUs, std::nullopt};
  return {*frameDurationUs, "exposure " + microseconds(exposureUs) + " -> " +
                                microseconds(*frameDurationUs) +
                                " (no longer than the pinned frame duration, mains_hz)"};
}

TimePerFrame timePerFrameOf(double frameDurationUs) {
  if (!(frameDurationUs >= 1.0) || frameDurationUs > 4.0e9)
    throw CameraError("frame duration " + std::to_string(frameDurationUs) +
                      " us: not a frame interval V4L2 can carry (1 us .. 4000 s)");
  const auto numerator = static_cast<std::uint32_t>(std::llround(frameDurationUs));
  const std::uint32_t denominator = 1000000;
  const std::uint32_t common = std::gcd(numerator, denominator);
  return {numerator / common, denominator / common};
}

std::optional<double> frameDurationUsOf(TimePerFrame interval) {
  if (interval.numerator == 0 || interval.denominator == 0) return std::nullopt;
  return 1.0e6 * double(interval.numerator) / double(interval.denominator);
}

std::int32_t powerLineFrequencyMenuValue(int mainsHz) {
  switch (mainsHz) {
    case 0:
      return 0;  // V4L2_CID_POWER_LINE_FREQUENCY_DISABLED
    case 50:
      return 1;  // V4L2_CID_POWER_LINE_FREQUENCY_50HZ
    case 60:
      return 2;  // V4L2_CID_POWER_LINE_FREQUENCY_60HZ
    default:
      throw CameraError("mains frequency " + std::to_string(mainsHz) +
                        " Hz: not 50, 60 or 0 (V4L2_CID_POWER_LINE_FREQUENCY has no other)");
  }
}

}  // namespace slicecap::hal
