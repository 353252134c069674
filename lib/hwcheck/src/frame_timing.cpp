// Frame timing from timestamps and sequence numbers.
#include "slicecap/hwcheck/frame_timing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace slicecap::hwcheck {

FrameTiming measureFrameTiming(const std::vector<SeenFrame>& frames) {
  FrameTiming timing;
  timing.frames = int(frames.size());
  if (frames.size() < 3) return timing;
  std::vector<double> steps;
  bool increasing = true;
  double toArrival = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const hal::FrameMetadata& m = frames[i].frame.metadata;
    toArrival = std::min(toArrival, double(frames[i].arrivalUs - m.timestampUs));
    if (i == 0) continue;
    const hal::FrameMetadata& p = frames[i - 1].frame.metadata;
    if (m.sequence <= p.sequence || m.timestampUs <= p.timestampUs) {
      increasing = false;
      continue;
    }
    const double seqStep = double(m.sequence - p.sequence);
    timing.dropped += int(m.sequence - p.sequence - 1);
    steps.push_back(double(m.timestampUs - p.timestampUs) / seqStep);
  }
  timing.hasTimestamps = increasing && !steps.empty();
  if (!timing.hasTimestamps) return timing;
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
  timing.periodUs = sorted[sorted.size() / 2];
  double sumSq = 0.0;
  for (double s : steps) sumSq += (s - timing.periodUs) * (s - timing.periodUs);
  timing.jitterUs = std::sqrt(sumSq / double(steps.size()));
  timing.timestampToArrivalUs = toArrival;
  return timing;
}

CheckItem frameTimingItem(const FrameTiming& timing, const std::string& cameraId) {
  CheckItem item{"frame timing", Verdict::Ok, "", ""};
  if (!timing.hasTimestamps) {
    item.verdict = Verdict::Fail;
    item.finding = cameraId + " gave " + std::to_string(timing.frames) +
                   " frames without increasing timestamps and sequence numbers";
    item.advice = "the LED cannot be timed against this camera's frames: use a camera whose "
                  "driver reports timestamps (libcamera, a V4L2 driver with buffer timestamps), "
                  "and set led_frames_per_state = 4 or more with led_alternate = true";
    return item;
  }
  char text[256];
  const int seen = timing.frames + timing.dropped;
  std::snprintf(text, sizeof text,
                "period %.1f us (%.2f fps), jitter %.1f us RMS, %d of %d frames dropped",
                timing.periodUs, 1e6 / timing.periodUs, timing.jitterUs, timing.dropped, seen);
  item.finding = text;
  const double dropFraction = double(timing.dropped) / double(std::max(seen, 1));
  if (dropFraction > 0.2) {
    item.verdict = Verdict::Fail;
    item.advice = "the camera loses most frames: check the cable and power, and that nothing "
                  "else loads the CPU (stop other camera users)";
  } else if (dropFraction > 0.02 || timing.jitterUs > 0.05 * timing.periodUs) {
    item.verdict = Verdict::Warn;
    item.advice = "frames come irregularly or are lost: a sweep gets fewer samples; check the "
                  "cable and the CPU load, or lower the resolution";
  }
  return item;
}

}  // namespace slicecap::hwcheck
