// The LED strobe in step with the camera's exposures: each live frame labelled from the LED's
// timeline over its rolling-shutter rows, and switches placed where no sample row is exposed.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/led_gate.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/hal/led.hpp"
#include "slicecap/hal/led_timeline.hpp"

namespace slicecap::daemon {

/// \brief How the strobe runs (slicecapd.conf: led_alternate, led_frames_per_state, led_guard_us,
/// readout_us).
struct StrobeSettings {
  bool alternate = true;    ///< false: the LED stays on (no room-light frames)
  int framesPerState = 2;   ///< frames planned with the LED on, then as many with it off
  double guardUs = 200.0;   ///< a switch's uncertainty either side (GPIO call, driver, LED rise)
  /// The sensor's readout time of a whole frame (top row to bottom row), from --check-hardware;
  /// used when the camera does not report its line time. nullopt: the frame period, the longest
  /// a rolling shutter can take, so classification errs towards "mixed".
  std::optional<double> readoutUs;

  /// \brief False with a reason naming the key for a value out of range.
  bool isValid(std::string* error = nullptr) const;
};

/// \brief One planned switch: at `atUs` on the camera's clock, to `on`, so that frame
/// `forSequence` is the first exposed under the new state.
struct PlannedSwitch {
  std::int64_t atUs = 0;
  bool on = false;
  std::uint64_t forSequence = 0;
};

/// \brief What the strobe saw of a sweep's live frames, for the status.
struct StrobeStats {
  std::uint64_t framesDelivered = 0;
  std::uint64_t framesDropped = 0;  ///< sequence gaps: frames the camera lost
  std::uint64_t framesClean = 0;    ///< one LED state over the rows of interest
  std::uint64_t framesMixed = 0;
  std::string timing;   ///< how exposure times are known, in words
  std::string warning;  ///< a weaker mode the camera forces, and what to configure; else empty
};

/// \brief The strobe of one sweep run. Single-threaded (the daemon's loop). The LED given must
/// record every switch on `commanded` (a hal::TimelineLed) on the camera's clock.
class LedStrobe {
 public:
  LedStrobe(StrobeSettings settings, hal::Led& led,
            std::shared_ptr<const hal::LedTimeline> commanded, std::string cameraId);

  /// \brief A live frame arrived (at `arrivalUs` on the camera's clock, as the daemon's clock
  /// reads it): sets its LED exposure from the timeline (when the camera says when it was
  /// exposed, else conservatively from its timestamp) and its `ledOn` label (the state over the
  /// latest rows of interest), and counts dropped frames.
  ///
  /// A camera whose timestamps are unusable (0, not increasing, after the arrival or more than
  /// 5 s before it) puts the strobe, for the rest
  /// of the run, in its untimed mode: the frame's timestamp is replaced by its arrival, it counts
  /// as exposed at any time in the kUntimedWindowPeriods frame periods before it, and the LED
  /// holds each state for at least kUntimedFramesPerState frames; stats().warning says so,
  /// naming the camera.
  void label(hal::Frame& frame, std::int64_t arrivalUs);
  /// \brief The rows the pipeline read in the latest located frame (nullopt: keep the last).
  void noteRows(const std::optional<capture::RowSpan>& rows);
  /// \brief The next switch to make at or after `earliestUs` (now plus the loop's latency), from
  /// the frames seen so far; nullopt while the frame timing is unknown or nothing alternates.
  std::optional<PlannedSwitch> plan(std::int64_t earliestUs) const;
  /// \brief Makes a planned switch. Throws what the LED throws.
  void fire(const PlannedSwitch& planned);

  /// Untimed mode: a frame may have been exposed up to this many frame periods before it reached
  /// the daemon (exposure, a rolling readout of most of a period, the ISP's hand-off, and a few
  /// frames queued in the camera's buffers while the loop was busy).
  static constexpr int kUntimedWindowPeriods = 6;
  /// Untimed mode: the LED holds each state at least this long, so about half of each block's
  /// frames fall wholly inside it.
  static constexpr int kUntimedFramesPerState = 12;

  const StrobeStats& stats() const { return stats_; }
  /// \brief Whether the camera's timestamps were found unusable (the untimed mode).
  bool untimed() const { return untimed_; }
  /// \brief "2 on, 2 off", or "on" without alternation.
  std::string pattern() const;

 private:
  bool desiredOn(std::uint64_t sequence) const;
  int framesPerState() const;
  double lineTimeUs(const hal::Frame& frame) const;

  StrobeSettings settings_;
  hal::Led& led_;
  std::shared_ptr<const hal::LedTimeline> commanded_;
  std::string cameraId_;
  StrobeStats stats_;
  // The latest frame's timing: the plan extrapolates from it.
  struct Timing {
    std::uint64_t sequence = 0;
    std::int64_t row0StartUs = 0;
    double exposureUs = 0.0;
    double lineTimeUs = 0.0;
    int heightPx = 0;
  };
  // The steps of label(), in its order.
  /// Enters the untimed mode at the first unusable timestamp; in it, times `m` by its arrival.
  void checkTimestamp(hal::FrameMetadata& m, std::int64_t arrivalUs);
  /// When the frame's rows were exposed, as far as the camera says; stats_ says how it is known.
  Timing timingOf(const hal::Frame& frame);
  /// The frame period from the latest frames' first-row starts.
  void notePeriod(std::uint64_t sequence, std::int64_t row0StartUs);
  /// The frame's LED exposure and its `ledOn` label over the rows of interest, counted.
  void labelLedState(hal::Frame& frame, const Timing& timing);
  std::optional<Timing> last_;
  std::vector<std::pair<std::uint64_t, std::int64_t>> recentStarts_;  // for the frame period
  std::optional<double> periodUs_;
  std::optional<capture::RowSpan> rows_;
  std::optional<std::int64_t> lastTimestampUs_;
  std::optional<bool> firedOn_;  // the state the last fire() set
  bool untimed_ = false;
  std::int64_t untimedLastUs_ = 0;
};

}  // namespace slicecap::daemon
