// What a sweep's samples say about the room light, for `slicecap status`: its level against the
// LED's, and how much it changes between the LED-off frames around a sample.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/control/reply_views.hpp"

namespace slicecap::daemon {

/// \brief The latest room-light figures (FrameOutcome::Measurement's roomToLed of samples,
/// roomChange of consecutive LED-off frames), and the warnings they call for.
class RoomLightWatch {
 public:
  /// \brief Room light above this fraction of the LED's over the white references: its shot noise
  /// and any change between the LED-off and LED-on frames weigh on every sample.
  static constexpr double kMaxRoomToLed = 0.25;
  /// \brief The room light moving by more than this fraction of the LED's light from one LED-off
  /// frame to the next (their median relative change times the room-to-LED ratio): a flicker the
  /// frame duration does not hide, which the subtraction leaves in the samples (a 30 % flicker
  /// at 15 % of the LED gives ~5 % at 33.3 ms frames; hidden, noise).
  static constexpr double kMaxRoomChangeToLed = 0.02;
  /// \brief The figures of this many latest frames count.
  static constexpr std::size_t kSamples = 32;

  /// \brief A new sweep run: nothing seen yet.
  void reset();
  /// \brief A settled outcome: a sample's room-to-LED ratio, an LED-off frame's change.
  void note(const capture::FrameOutcome& outcome);
  /// \brief The latest samples' median room-to-LED ratio (none before the first sample).
  std::optional<double> roomToLed() const;
  /// \brief The latest LED-off frames' median change, relative to the room light (none before
  /// two consecutive ones).
  std::optional<double> roomChange() const;
  /// \brief roomChange() x roomToLed(): the change as a fraction of the LED's light.
  std::optional<double> roomChangeToLed() const;
  /// \brief A sentence for each figure beyond its limit, naming it and what to do.
  std::vector<std::string> warnings() const;
  /// \brief The status's "room_light" figures (none before the first sample).
  control::RoomLightView view() const;

 private:
  std::deque<double> ratios_, changes_;
};

}  // namespace slicecap::daemon
