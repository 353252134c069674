// The LED's switches on the camera clock, and their effect on a rolling-shutter frame's rows.
#include "slicecap/hal/led_timeline.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slicecap/hal/hal_error.hpp"

namespace slicecap::hal {

const char* toString(LedExposure::State state) {
  switch (state) {
    case LedExposure::State::Off:
      return "off";
    case LedExposure::State::On:
      return "on";
    case LedExposure::State::Mixed:
      break;
  }
  return "mixed";
}

LedExposure::State LedExposure::stateOver(int firstRow, int lastRow) const {
  if (lastRow < firstRow) std::swap(firstRow, lastRow);
  const double startUs = double(row0StartUs) + std::max(0, firstRow) * lineTimeUs;
  const double endUs = double(row0StartUs) + std::max(0, lastRow) * lineTimeUs + exposureUs;
  bool state = onAtStart;
  for (const LedChange& change : changes) {
    const double t = double(change.timeUs);
    if (t + guardUs <= startUs) {
      state = change.on;
      continue;
    }
    if (t - guardUs < endUs) return State::Mixed;
    break;
  }
  return state ? State::On : State::Off;
}

double LedExposure::onFraction(int row) const {
  if (exposureUs <= 0) return onAtStart ? 1.0 : 0.0;
  const double startUs = double(row0StartUs) + row * lineTimeUs;
  const double endUs = startUs + exposureUs;
  double onUs = 0.0, cursor = startUs;
  bool state = onAtStart;
  for (const LedChange& change : changes) {
    const double t = double(change.timeUs);
    if (t <= cursor) {
      state = change.on;
      continue;
    }
    const double until = std::min(t, endUs);
    if (state) onUs += until - cursor;
    cursor = until;
    state = change.on;
    if (cursor >= endUs) break;
  }
  if (cursor < endUs && state) onUs += endUs - cursor;
  return onUs / exposureUs;
}

void LedTimeline::record(std::int64_t timeUs, bool on) {
  std::lock_guard lock(mutex_);
  if (!changes_.empty() && timeUs < changes_.back().timeUs)
    throw HalError("LED timeline: a switch at " + std::to_string(timeUs) +
                   " us is before the last one at " +
                   std::to_string(changes_.back().timeUs) + " us");
  const bool current = changes_.empty() ? initiallyOn_ : changes_.back().on;
  if (current == on) return;
  changes_.push_back({timeUs, on});
}

bool LedTimeline::stateAtLocked(std::int64_t timeUs) const {
  const auto after = std::upper_bound(changes_.begin(), changes_.end(), timeUs,
                                      [](std::int64_t t, const LedChange& c) { return t < c.timeUs; });
  return after == changes_.begin() ? initiallyOn_ : (after - 1)->on;
}

bool LedTimeline::stateAt(std::int64_t timeUs) const {
  std::lock_guard lock(mutex_);
  return stateAtLocked(timeUs);
}

double LedTimeline::onTimeUs(double startUs, double endUs) const {
  std::lock_guard lock(mutex_);
  if (endUs <= startUs) return 0.0;
  const auto first = std::upper_bound(
      changes_.begin(), changes_.end(), startUs,
      [](double t, const LedChange& c) { return t < double(c.timeUs); });
  bool state = first == changes_.begin() ? initiallyOn_ : (first - 1)->on;
  double cursor = startUs, onUs = 0.0;
  for (auto it = first; it != changes_.end() && double(it->timeUs) < endUs; ++it) {
    if (state) onUs += double(it->timeUs) - cursor;
    cursor = double(it->timeUs);
    state = it->on;
  }
  if (state) onUs += endUs - cursor;
  return onUs;
}

LedExposure LedTimeline::exposureOf(std::int64_t row0StartUs, double lineTimeUs,
                                    double exposureUs, int heightPx, double guardUs) const {
  std::lock_guard lock(mutex_);
  LedExposure exposure;
  exposure.row0StartUs = row0StartUs;
  exposure.lineTimeUs = lineTimeUs;
  exposure.exposureUs = exposureUs;
  exposure.guardUs = guardUs;
  // Switches within the guard before the first row count too: they make it mixed.
  const double fromUs = double(row0StartUs) - guardUs;
  const double toUs =
      double(row0StartUs) + std::max(0, heightPx - 1) * lineTimeUs + exposureUs + guardUs;
  const std::int64_t from = static_cast<std::int64_t>(std::floor(fromUs));
  exposure.onAtStart = stateAtLocked(from);
  for (const LedChange& change : changes_)
    if (change.timeUs > from && double(change.timeUs) < toUs) exposure.changes.push_back(change);
  return exposure;
}

std::optional<std::int64_t> LedTimeline::firstSwitchAfter(std::int64_t timeUs, bool on) const {
  std::lock_guard lock(mutex_);
  for (const LedChange& change : changes_)
    if (change.timeUs > timeUs && change.on == on) return change.timeUs;
  return std::nullopt;
}

void LedTimeline::forgetBefore(std::int64_t timeUs) {
  std::lock_guard lock(mutex_);
  const auto keepFrom = std::upper_bound(
      changes_.begin(), changes_.end(), timeUs,
      [](std::int64_t t, const LedChange& c) { return t < c.timeUs; });
  if (keepFrom == changes_.begin()) return;
  initiallyOn_ = (keepFrom - 1)->on;
  changes_.erase(changes_.begin(), keepFrom);
}

std::size_t LedTimeline::size() const {
  std::lock_guard lock(mutex_);
  return changes_.size();
}

TimelineLed::TimelineLed(std::unique_ptr<Led> inner, const Clock& clock,
                         std::shared_ptr<LedTimeline> timeline, std::int64_t switchDelayUs)
    : inner_(std::move(inner)),
      clock_(clock),
      timeline_(std::move(timeline)),
      switchDelayUs_(switchDelayUs) {
  if (!inner_ || !timeline_) throw HalError("TimelineLed needs an LED and a timeline");
}

void TimelineLed::set(bool on) {
  inner_->set(on);
  timeline_->record(clock_.nowUs() + switchDelayUs_, on);
}

}  // namespace slicecap::hal
