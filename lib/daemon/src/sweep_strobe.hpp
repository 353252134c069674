// A live sweep's LED strobe on the event loop: each frame labelled with the LED's state over its
// rows, the next switch timed from what the frames showed, and the strobe's figures for the status.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "slicecap/control/reply_views.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/daemon/led_strobe.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/hal/led.hpp"
#include "slicecap/hal/led_timeline.hpp"

namespace slicecap::daemon {

/// \brief The strobe of a live camera's sweep run, from its first frame after the calibration to
/// the sweep's stop (LedStrobe), with its switch timer on the loop. Single-threaded (the loop).
class SweepStrobe {
 public:
  /// \brief What a switch made by the timer tells the sweep: the LED went on (a new pair, which
  /// may switch an HDR sweep's exposure), or the LED failed (the message names it).
  struct Listener {
    std::function<void()> switchedOn;
    std::function<void(const std::string& error)> failed;
  };

  /// \brief Every argument outlives this; `led` records each switch on `commanded` (the daemon's
  /// hal::TimelineLed), on `clock`, the camera's clock.
  SweepStrobe(EventLoop& loop, hal::Led& led, std::shared_ptr<hal::LedTimeline> commanded,
              hal::Clock& clock, StrobeSettings settings, Listener listener);
  ~SweepStrobe();
  SweepStrobe(const SweepStrobe&) = delete;
  SweepStrobe& operator=(const SweepStrobe&) = delete;

  /// \brief A live frame: starts the run at the first (the LED lit, as each block starts) and
  /// labels the frame from the LED's timeline over its rows. Throws what the LED throws.
  void label(hal::Frame& frame, const std::string& cameraId);
  /// \brief The rows the pipeline read in a settled outcome (LedStrobe::noteRows).
  void noteRows(const std::optional<capture::RowSpan>& rows);
  /// \brief After a live frame: the next switch, timed from the rows noted so far.
  void scheduleSwitch();
  /// \brief The sweep stopped: no switch is pending; the run's figures stay for the status.
  void stop();

  /// \brief The status's "camera_frames" (this run's, or the last one's) and the strobe's warning.
  void describe(control::StatusView& status) const;

 private:
  void fire(const PlannedSwitch& planned);

  EventLoop& loop_;
  hal::Led& led_;
  std::shared_ptr<hal::LedTimeline> commanded_;
  hal::Clock& clock_;
  StrobeSettings settings_;
  Listener listener_;
  std::optional<LedStrobe> run_;
  std::optional<EventLoop::TimerId> switchTimer_;
  std::optional<PlannedSwitch> scheduled_;
  // The last run's figures and pattern (the untimed mode lengthens it), for the status.
  std::optional<StrobeStats> lastStats_;
  std::string lastPattern_;
};

}  // namespace slicecap::daemon
