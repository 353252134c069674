// A live sweep's LED strobe and its switch timer (docs/design.md, the daemon's threads).
#include "sweep_strobe.hpp"

#include <algorithm>

namespace slicecap::daemon {

SweepStrobe::SweepStrobe(EventLoop& loop, hal::Led& led, std::shared_ptr<hal::LedTimeline> commanded,
                         hal::Clock& clock, StrobeSettings settings, Listener listener)
    : loop_(loop),
      led_(led),
      commanded_(std::move(commanded)),
      clock_(clock),
      settings_(std::move(settings)),
      listener_(std::move(listener)) {}

SweepStrobe::~SweepStrobe() {
  stop();
}

void SweepStrobe::label(hal::Frame& frame, const std::string& cameraId) {
  if (!run_) {
    run_.emplace(settings_, led_, commanded_, cameraId);
    lastPattern_ = run_->pattern();
    led_.set(true);  // each block starts lit; the metering may have left it so already
  }
  run_->label(frame, clock_.nowUs());
  // What no frame can still need: a few seconds are plenty for any queue of frames.
  commanded_->forgetBefore(clock_.nowUs() - 5'000'000);
}

void SweepStrobe::noteRows(const std::optional<capture::RowSpan>& rows) {
  if (run_) run_->noteRows(rows);
}

void SweepStrobe::scheduleSwitch() {
  if (!run_) return;
  // A planned switch stays planned: frames queued behind a slow one arrive before its time,
  // and planning again at each would put it off for ever (the LED would never switch).
  if (scheduled_) return;
  const std::int64_t nowUs = clock_.nowUs();
  // The loop wakes a little late; a switch planned sooner than this is left for the next.
  constexpr std::int64_t kWakeLatencyUs = 1000;
  const std::optional<PlannedSwitch> next = run_->plan(nowUs + kWakeLatencyUs);
  if (!next) return;
  scheduled_ = next;
  switchTimer_ = loop_.addTimer(std::chrono::microseconds(std::max<std::int64_t>(1, next->atUs - nowUs)),
                                false, [this, planned = *next] { fire(planned); });
}

void SweepStrobe::fire(const PlannedSwitch& planned) {
  switchTimer_.reset();
  scheduled_.reset();
  if (!run_) return;
  try {
    run_->fire(planned);
  } catch (const std::exception& error) {
    listener_.failed(error.what());
    return;
  }
  if (planned.on) listener_.switchedOn();
}

void SweepStrobe::stop() {
  if (switchTimer_) loop_.cancelTimer(*switchTimer_);
  switchTimer_.reset();
  scheduled_.reset();
  if (run_) {
    lastStats_ = run_->stats();
    lastPattern_ = run_->pattern();  // the untimed mode lengthens it
  }
  run_.reset();
}

void SweepStrobe::describe(control::StatusView& status) const {
  const std::optional<StrobeStats> shown = run_ ? run_->stats() : lastStats_;
  if (!shown) return;
  const double judged = double(shown->framesClean + shown->framesMixed);
  status.cameraFrames = control::CameraFramesView{
      shown->framesDelivered, shown->framesDropped, run_ ? run_->pattern() : lastPattern_,
      judged > 0 ? double(shown->framesClean) / judged : 0.0, shown->timing};
  if (!shown->warning.empty()) status.warnings.push_back(shown->warning);
}

}  // namespace slicecap::daemon
