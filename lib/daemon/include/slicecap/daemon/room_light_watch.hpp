// What a sweep's samples say about the room light, for `slicecap status`: its level against the
// LED's, and how much it changes between the LED-off frames around a sample.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "slicecap/capture/frame_outcome.hpp"

namespace slicecap::daemon {

/// \brief The latest samples' room-light figures (FrameOutcome::Measurement's roomToLed and
/// roomChangeToLed), and the warnings they call for.
class RoomLightWatch {
 public:
  /// \brief Room light above this fraction of the LED's over the white references: its shot noise
  /// and any change between the LED-off and LED-on frames weigh on every sample.
  static constexpr double kMaxRoomToLed = 0.25;
  /// \brief The LED-off frames around a sample apart by more than this fraction of the LED's light
  /// (RMS over the latest samples): a flicker the frame duration does not hide (a 30 % flicker at
  /// 15 % of the LED moves them ~6 %; noise and a hidden flicker well under 1 %).
  static constexpr double kMaxRoomChangeToLed = 0.02;
  /// \brief The figures of this many latest samples count.
  static constexpr std::size_t kSamples = 32;

  /// \brief A new sweep run: nothing seen yet.
  void reset();
  /// \brief An accepted sample's measurement.
  void note(const capture::FrameOutcome::Measurement& measurement);
  /// \brief The median room-to-LED ratio and the RMS change of the latest samples (none before
  /// the first).
  std::optional<double> roomToLed() const;
  std::optional<double> roomChangeToLed() const;
  /// \brief A sentence for each figure beyond its limit, naming it and what to do.
  std::vector<std::string> warnings() const;
  /// \brief The status's "room_light" object ({} before the first sample).
  nlohmann::json summary() const;

 private:
  std::deque<double> ratios_, changes_;
};

}  // namespace slicecap::daemon
