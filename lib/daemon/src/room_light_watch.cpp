// The room light as the sweep's samples see it, and the status's warnings about it.
#include "slicecap/daemon/room_light_watch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace slicecap::daemon {
namespace {

void keepLatest(std::deque<double>& values, double value) {
  values.push_back(value);
  while (values.size() > RoomLightWatch::kSamples) values.pop_front();
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %%", 100.0 * fraction);
  return text;
}

}  // namespace

void RoomLightWatch::reset() {
  ratios_.clear();
  changes_.clear();
}

void RoomLightWatch::note(const capture::FrameOutcome& outcome) {
  const capture::FrameOutcome::Measurement& m = outcome.measurement;
  if (outcome.kind == capture::FrameOutcome::Kind::Sample && m.roomToLed &&
      std::isfinite(*m.roomToLed))
    keepLatest(ratios_, *m.roomToLed);
  if (outcome.kind == capture::FrameOutcome::Kind::Ambient && m.roomChange &&
      std::isfinite(*m.roomChange))
    keepLatest(changes_, *m.roomChange);
}

namespace {

// The median: a frame the light arm shades, or a pair straddling a jump of the hand, is one
// outlier; a flicker the frame duration does not hide moves most pairs.
std::optional<double> median(const std::deque<double>& values) {
  if (values.empty()) return std::nullopt;
  std::vector<double> sorted(values.begin(), values.end());
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  return sorted[sorted.size() / 2];
}

}  // namespace

std::optional<double> RoomLightWatch::roomToLed() const {
  return median(ratios_);
}

std::optional<double> RoomLightWatch::roomChange() const {
  return median(changes_);
}

std::optional<double> RoomLightWatch::roomChangeToLed() const {
  const std::optional<double> change = roomChange(), ratio = roomToLed();
  if (!change || !ratio) return std::nullopt;
  return *change * *ratio;
}

std::vector<std::string> RoomLightWatch::warnings() const {
  std::vector<std::string> out;
  if (const std::optional<double> ratio = roomToLed(); ratio && *ratio > kMaxRoomToLed)
    out.push_back("room light: " + percent(*ratio) + " of the LED's light on the white references " +
                  "(more than " + percent(kMaxRoomToLed) + "): dim the room or shade the target");
  if (const std::optional<double> change = roomChangeToLed(); change && *change > kMaxRoomChangeToLed)
    out.push_back("room light: it changes by " + percent(*change) + " of the LED's light from " +
                  "one LED-off frame to the next (more than " + percent(kMaxRoomChangeToLed) +
                  "): a lamp flickers and the frame duration does not hide it; set mains_hz to " +
                  "the room's mains (slicecapd --check-hardware measures the flicker), or switch " +
                  "that lamp off");
  return out;
}

control::RoomLightView RoomLightWatch::view() const {
  return {roomToLed(), roomChange(), roomChangeToLed()};
}

}  // namespace slicecap::daemon
