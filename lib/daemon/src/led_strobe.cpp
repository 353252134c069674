// The strobe: labels from the LED's timeline over a frame's rows, switches between exposures.
#include "slicecap/daemon/led_strobe.hpp"

#include <algorithm>
#include <cmath>

namespace slicecap::daemon {
namespace {

// A period to assume before two frames have shown the real one (30 frames/s).
constexpr double kAssumedPeriodUs = 33333.0;

// What the untimed mode costs and how to leave it, naming the camera.
std::string untimedWarning(const std::string& cameraId, int framesPerState) {
  return "camera " + cameraId + " reports no usable frame timestamps (0, not increasing, or not on the LED's clock): frames " +
         "are timed by their arrival, each judged exposed during the " +
         std::to_string(LedStrobe::kUntimedWindowPeriods) + " frame periods before it, and the LED holds each " +
         "state for " + std::to_string(framesPerState) +
         " frames (fewer frames are clean, rejected as led_transition). Use a driver or camera that "
         "stamps its frames (libcamera's SensorTimestamp, V4L2 buffer timestamps); a larger "
         "led_frames_per_state keeps more frames";
}

}  // namespace

bool StrobeSettings::isValid(std::string* error) const {
  const auto fail = [error](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (framesPerState < 1 || framesPerState > 30)
    return fail("led_frames_per_state must be 1..30, not " + std::to_string(framesPerState));
  if (!(guardUs >= 0.0 && guardUs <= 10000.0))
    return fail("led_guard_us must be 0..10000, not " + std::to_string(guardUs));
  if (readoutUs && !(*readoutUs > 0.0 && *readoutUs <= 1e6))
    return fail("readout_us must be in (0, 1e6], not " + std::to_string(*readoutUs));
  return true;
}

LedStrobe::LedStrobe(StrobeSettings settings, hal::Led& led,
                     std::shared_ptr<const hal::LedTimeline> commanded, std::string cameraId)
    : settings_(std::move(settings)),
      led_(led),
      commanded_(std::move(commanded)),
      cameraId_(std::move(cameraId)) {}

int LedStrobe::framesPerState() const {
  return untimed_ ? std::max(settings_.framesPerState, kUntimedFramesPerState) : settings_.framesPerState;
}

bool LedStrobe::desiredOn(std::uint64_t sequence) const {
  if (!settings_.alternate) return true;
  return (sequence / static_cast<std::uint64_t>(framesPerState())) % 2 == 0;
}

std::string LedStrobe::pattern() const {
  if (!settings_.alternate) return "on";
  const std::string n = std::to_string(framesPerState());
  return n + " on, " + n + " off";
}

double LedStrobe::lineTimeUs(const hal::Frame& frame) const {
  if (frame.metadata.lineTimeUs) return *frame.metadata.lineTimeUs;
  const int height = std::max(1, frame.image.height);
  return settings_.readoutUs.value_or(periodUs_.value_or(kAssumedPeriodUs)) / height;
}

void LedStrobe::label(hal::Frame& frame, std::int64_t arrivalUs) {
  checkTimestamp(frame.metadata, arrivalUs);
  const hal::FrameMetadata& m = frame.metadata;
  ++stats_.framesDelivered;
  if (last_ && m.sequence > last_->sequence + 1) stats_.framesDropped += m.sequence - last_->sequence - 1;
  const Timing timing = timingOf(frame);
  notePeriod(m.sequence, timing.row0StartUs);
  labelLedState(frame, timing);
  last_ = timing;
}

void LedStrobe::checkTimestamp(hal::FrameMetadata& m, std::int64_t arrivalUs) {
  // A timestamp of 0 (a driver that stamps nothing) or one that does not increase cannot place
  // the frame against the LED's timeline; nor can any later one of this camera be trusted.
  // So is one far from the frame's arrival on the LED's clock (the camera's clock is another, or
  // its stamp garbage): a frame reaches the daemon after its exposure, and a few buffers' worth,
  // or a stall of the loop, later at most (the LED's timeline is kept 5 s).
  constexpr std::int64_t kEarliestStampUs = 5'000'000, kLatestStampUs = 1'000;
  if (!untimed_ &&
      (m.timestampUs <= 0 || (lastTimestampUs_ && m.timestampUs <= *lastTimestampUs_) ||
       m.timestampUs > arrivalUs + kLatestStampUs || m.timestampUs < arrivalUs - kEarliestStampUs)) {
    untimed_ = true;
    recentStarts_.clear();
    periodUs_.reset();
  }
  lastTimestampUs_ = m.timestampUs;
  if (untimed_) {
    // Downstream (samples, room-light terms, record_frames) needs increasing times on the LED's
    // clock: the arrival is the only one there is.
    m.timestampUs = std::max(arrivalUs, untimedLastUs_ + 1);
    untimedLastUs_ = m.timestampUs;
    m.exposureStartUs.reset();
  }
}

LedStrobe::Timing LedStrobe::timingOf(const hal::Frame& frame) {
  const hal::FrameMetadata& m = frame.metadata;
  const double period = periodUs_.value_or(kAssumedPeriodUs);
  Timing timing;
  timing.sequence = m.sequence;
  timing.heightPx = frame.image.height;
  if (untimed_) {
    timing.row0StartUs = m.timestampUs - static_cast<std::int64_t>(kUntimedWindowPeriods * period);
    timing.exposureUs = kUntimedWindowPeriods * period;
    timing.lineTimeUs = 0.0;
    stats_.timing = "timestamps unusable: a frame counts as exposed during the " +
                    std::to_string(kUntimedWindowPeriods) +
                    " frame periods before it reached the daemon";
    stats_.warning = untimedWarning(cameraId_, framesPerState());
  } else if (m.exposureStartUs && m.exposureUs > 0) {
    timing.row0StartUs = *m.exposureStartUs;
    timing.exposureUs = m.exposureUs;
    timing.lineTimeUs = lineTimeUs(frame);
    stats_.timing = m.lineTimeUs ? "exposure start and line time from the camera"
                    : settings_.readoutUs
                        ? "exposure start from the camera, readout_us from the configuration"
                        : "exposure start from the camera, readout assumed a whole frame period";
    stats_.warning.clear();
  } else {
    // The camera does not say when its frames were exposed (or for how long): any time in the
    // two frame periods before its timestamp, read as one long global exposure. Correct but
    // wasteful: few frames are clean unless the LED holds its state for several frames.
    timing.row0StartUs = m.timestampUs - static_cast<std::int64_t>(2 * period);
    timing.exposureUs = 3 * period;
    timing.lineTimeUs = 0.0;
    stats_.timing = "exposure times unknown: a frame counts as exposed from two periods before "
                    "its timestamp to one after";
    stats_.warning = "camera " + cameraId_ +
                     " does not report when its frames were exposed: LED states are judged "
                     "conservatively and many frames are rejected as led_transition; set "
                     "led_frames_per_state = 4 or more, or lock the exposure (exposure_us)";
  }
  return timing;
}

void LedStrobe::notePeriod(std::uint64_t sequence, std::int64_t row0StartUs) {
  recentStarts_.emplace_back(sequence, row0StartUs);
  if (recentStarts_.size() > 16) recentStarts_.erase(recentStarts_.begin());
  if (recentStarts_.size() >= 2) {
    const auto& [s0, t0] = recentStarts_.front();
    const auto& [s1, t1] = recentStarts_.back();
    if (s1 > s0 && t1 > t0) periodUs_ = double(t1 - t0) / double(s1 - s0);
  }
}

void LedStrobe::labelLedState(hal::Frame& frame, const Timing& timing) {
  const int height = std::max(1, frame.image.height);
  hal::LedExposure exposure = commanded_->exposureOf(timing.row0StartUs, timing.lineTimeUs,
                                                     timing.exposureUs, height, settings_.guardUs);
  const capture::RowSpan rows = rows_.value_or(capture::RowSpan{0, height - 1});
  const hal::LedExposure::State state = exposure.stateOver(rows.first, rows.last);
  if (state == hal::LedExposure::State::Mixed) {
    ++stats_.framesMixed;
    frame.metadata.ledOn = exposure.onFraction((rows.first + rows.last) / 2) >= 0.5;
  } else {
    ++stats_.framesClean;
    frame.metadata.ledOn = state == hal::LedExposure::State::On;
  }
  frame.metadata.ledExposure = std::move(exposure);
}

void LedStrobe::noteRows(const std::optional<capture::RowSpan>& rows) {
  if (rows) rows_ = rows;
}

std::optional<PlannedSwitch> LedStrobe::plan(std::int64_t earliestUs) const {
  if (!settings_.alternate || !last_ || !periodUs_) return std::nullopt;
  const Timing& t = *last_;
  const capture::RowSpan rows = rows_.value_or(capture::RowSpan{0, std::max(0, t.heightPx - 1)});
  // The latest frame can be long past (frames queue behind a slow one): start from the first
  // frame whose switch time is not, then look one whole pattern on.
  const double sinceLastUs = double(earliestUs) -
                             (double(t.row0StartUs) + rows.last * t.lineTimeUs + t.exposureUs + settings_.guardUs);
  const std::uint64_t first =
      t.sequence + 1 + (sinceLastUs > 0 ? static_cast<std::uint64_t>(sinceLastUs / *periodUs_) : 0);
  const auto limit = first + 2 * static_cast<std::uint64_t>(settings_.framesPerState) + 2;
  for (std::uint64_t j = first; j < limit; ++j) {
    if (desiredOn(j) == desiredOn(j - 1)) continue;
    // A switch to the state the LED is already in: the one before it fired late (a busy loop)
    // and the switch back is past. The next switch away keeps the blocks alternating, shorter
    // by the delay, where skipping a whole pattern would hold the LED in one state for twice as
    // long and the other state's frames would be missing.
    if (firedOn_ && desiredOn(j) == *firedOn_) continue;
    // Just after the last row of interest of frame j - 1 has been exposed: frame j's rows of
    // interest start (period - exposure - their readout span) later, clean when that is
    // positive; else frame j is the one that comes out mixed.
    const double previousStartUs = double(t.row0StartUs) + double(j - 1 - t.sequence) * *periodUs_;
    const double atUs = previousStartUs + rows.last * t.lineTimeUs + t.exposureUs + settings_.guardUs;
    if (atUs < double(earliestUs)) continue;
    return PlannedSwitch{static_cast<std::int64_t>(std::ceil(atUs)), desiredOn(j), j};
  }
  return std::nullopt;
}

void LedStrobe::fire(const PlannedSwitch& planned) {
  led_.set(planned.on);
  firedOn_ = planned.on;
}

}  // namespace slicecap::daemon
