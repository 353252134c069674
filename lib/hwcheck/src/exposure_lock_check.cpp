// The exposure-lock check: lock, then watch the frames' metadata and brightness.
#include "slicecap/hwcheck/exposure_lock_check.hpp"

#include <cmath>
#include <cstdio>
#include <numeric>

#include "slicecap/hwcheck/hardware_check_error.hpp"

namespace slicecap::hwcheck {
namespace {

double brightness(const hal::Frame& frame, const WhiteRows* whites) {
  const capture::CodeTable& codes = capture::CodeTable::srgb();
  if (whites && whites->firstRow >= 0) return whites->mean(frame, codes);
  double sum = 0.0;
  const auto& s = frame.image.samples;
  // Every 7th sample: a mean of the frame, cheaply; decoded so that a change in exposure is a
  // change in level even on a bent curve (sRGB: the nearest a curve can be without measuring).
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.size(); i += 7, ++n)
    sum += frame.encoding == PixelEncoding::Srgb8 ? codes[s[i]]
                                                  : hal::linear16Value(s[i], frame.black16);
  return n ? sum / double(n) : 0.0;
}

}  // namespace

ExposureLockResult checkExposureLock(CheckRig& rig, const WhiteRows* whites, int maxFrames) {
  ExposureLockResult result;
  const std::optional<SeenFrame> before = rig.next(std::chrono::milliseconds(1000));
  if (!before) throw HardwareCheckError(rig.camera().id() + ": no frame for a second");
  const hal::FrameMetadata& m0 = before->frame.metadata;
  result.reportsExposure = m0.exposureUs > 0.0;
  result.fromUs = m0.exposureUs;
  // Half the exposure: a change the brightness shows clearly, without going dark.
  result.toUs = result.reportsExposure ? m0.exposureUs / 2.0 : 5000.0;
  // White references clipped before the lock may stay clipped at half the exposure (a bright
  // room adds to the LED, and the camera's own exposure need not leave them room): then the whole
  // frame, mostly darker than they, shows the change.
  if (whites && brightness(before->frame, whites) > 0.95) whites = nullptr;
  const double level0 = brightness(before->frame, whites);
  const std::int64_t lockUs = rig.clock().nowUs();
  const hal::ExposureLock lock =
      rig.lock({result.toUs, result.reportsExposure ? std::optional(m0.gain) : std::nullopt});
  if (!lock.locked) {
    result.refused = true;
    result.note = lock.reason;
    return result;
  }
  result.toUs = lock.locked->exposureUs;
  const double expectedLog = result.reportsExposure
                                 ? std::log(lock.locked->exposureUs * lock.locked->gain.value_or(m0.gain) /
                                            (m0.exposureUs * m0.gain))
                                 : std::log(0.5);
  std::optional<std::uint64_t> firstAfterLock;
  for (int n = 0; n < maxFrames; ++n) {
    const std::optional<SeenFrame> seen = rig.next(std::chrono::milliseconds(1000));
    if (!seen) throw HardwareCheckError(rig.camera().id() + ": no frame for a second");
    const hal::FrameMetadata& m = seen->frame.metadata;
    if (m.timestampUs <= lockUs) continue;  // started before the lock: cannot have it
    if (!firstAfterLock) firstAfterLock = m.sequence;
    const int delay = int(m.sequence - *firstAfterLock);
    if (!result.metadataDelayFrames && result.reportsExposure &&
        std::abs(m.exposureUs - result.toUs) <= 0.02 * result.toUs + 1.0)
      result.metadataDelayFrames = delay;
    const double level = brightness(seen->frame, whites);
    if (!result.brightnessDelayFrames && level0 > 0.0 && level > 0.0 &&
        std::log(level / level0) / expectedLog > 1.0 / 3.0)
      result.brightnessDelayFrames = delay;
    if (result.brightnessDelayFrames && (result.metadataDelayFrames || !result.reportsExposure))
      break;
  }
  return result;
}

CheckItem exposureLockItem(const ExposureLockResult& r, const std::string& cameraId) {
  CheckItem item{"exposure lock", Verdict::Ok, "", ""};
  if (r.refused) {
    item.verdict = Verdict::Fail;
    item.finding = cameraId + " refused to lock its exposure: " + r.note;
    item.advice = "the sweep needs a fixed exposure: use a camera whose driver takes manual "
                  "exposure (libcamera ExposureTime, V4L2 exposure_time_absolute)";
    return item;
  }
  char text[256];
  const auto frames = [](const std::optional<int>& n) {
    return n ? std::to_string(*n) + " frame(s)" : std::string("never (within the frames watched)");
  };
  std::snprintf(text, sizeof text, "locked %.0f us (from %.0f us): reported after ", r.toUs, r.fromUs);
  item.finding = std::string(text) + (r.reportsExposure ? frames(r.metadataDelayFrames)
                                                          : std::string("- (frames report no exposure)")) +
                 ", brightness changed after " + frames(r.brightnessDelayFrames);
  if (!r.brightnessDelayFrames) {
    item.verdict = Verdict::Fail;
    item.advice = "the lock did not change the picture: the camera may keep its auto exposure; "
                  "check that nothing else controls it, or set exposure_us and gain by hand";
  } else if (!r.reportsExposure) {
    item.verdict = Verdict::Warn;
    item.advice = cameraId + " does not report each frame's exposure: the response bracket cannot "
                  "be fitted (frames are decoded as sRGB) and frames are timed conservatively; "
                  "set led_frames_per_state = 4 or more";
  } else if (!r.metadataDelayFrames || *r.metadataDelayFrames != *r.brightnessDelayFrames) {
    item.verdict = Verdict::Warn;
    item.advice = "the frames' reported exposure and their brightness disagree on when the lock "
                  "took effect: frames may be labelled with the wrong exposure; wait a few frames "
                  "after a lock (the metering does)";
  }
  return item;
}

}  // namespace slicecap::hwcheck
