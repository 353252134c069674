// Room light as mains-powered lamps give it: a mean level modulated at twice the mains frequency.
#pragma once

#include <optional>
#include <string>

namespace slicecap::hal {

/// \brief A lamp on AC mains: its light rises and falls twice per mains cycle (100 Hz on 50 Hz
/// mains, 120 Hz on 60 Hz). Modelled as its fundamental, mean * (1 + depth * cos(2 pi hz t +
/// phase)): `depth` is IEEE Std 1789-2015's "percent flicker" / 100, (max - min) / (max + min).
/// A full-wave rectified waveform has harmonics at 200, 300 Hz too; over the exposures a camera
/// uses (>= 0.5 ms) they are attenuated far more than the fundamental, which sets what a frame
/// sees. t is on the steady clock (the mains does not know when the camera started); phase in
/// cycles.
struct RoomFlicker {
  double hz = 0.0;     ///< 0: steady light
  double depth = 0.0;  ///< 0..1
  double phaseCycles = 0.0;

  /// \brief The light averaged over [startUs, startUs + durationUs), as a multiple of the mean:
  /// what a row exposed over that window integrates, per unit of time. Exactly 1 when the window
  /// spans whole flicker periods.
  double meanFactor(double startUs, double durationUs) const;
  /// \brief The factor at one instant.
  double factorAt(double timeUs) const;
  /// \brief False with a reason naming the field when a value is out of range (hz 0 or 1..1000,
  /// depth 0..1).
  bool isValid(std::string* error = nullptr) const;
};

/// \brief The flicker frequency of lamps on `mainsHz` mains (50 or 60): twice it.
double flickerHzOfMains(int mainsHz);

/// \brief The frame duration slicecapd asks a camera for on `mainsHz` mains (50, 60; 0: none):
/// the shortest whole number of flicker periods at or above a 30 fps camera's 33.3 ms, i.e. 40 ms
/// (4 x 10 ms) on 50 Hz and 33.33 ms (4 x 8.33 ms) on 60 Hz. Consecutive frames then start at the
/// same flicker phase, so each row of an LED-off frame saw the same room light as that row of the
/// LED-on frames it is subtracted from, at any exposure (docs/real-sensors.md, "Room light").
std::optional<double> frameDurationUsForMains(int mainsHz);

}  // namespace slicecap::hal
