// What the LED did while a rolling-shutter frame's rows were exposed: a value carried with the frame.
#pragma once

#include <cstdint>
#include <vector>

namespace slicecap::hal {

/// \brief One switch of the LED: from `timeUs` on, it is `on`.
struct LedChange {
  std::int64_t timeUs = 0;
  bool on = false;
};

/// \brief The LED over a frame's rows. A rolling shutter exposes row r over [row0StartUs + r *
/// lineTimeUs, + exposureUs): an LED switched meanwhile lights some rows and not others. Built by
/// whoever drives the LED (the daemon, from its timeline); a value, so it travels with the frame.
struct LedExposure {
  std::int64_t row0StartUs = 0;  ///< start of row 0's exposure, on the timeline's clock
  double lineTimeUs = 0.0;       ///< start-to-start delay of consecutive rows (0: global shutter)
  double exposureUs = 0.0;
  bool onAtStart = false;          ///< the LED's state at row 0's start
  std::vector<LedChange> changes;  ///< switches after row0StartUs, in time order
  /// A switch counts this long either side of its recorded time (GPIO and driver latency, the
  /// LED's rise and fall): a row exposed within that is not trusted.
  double guardUs = 0.0;

  enum class State { Off, On, Mixed };
  /// \brief On (Off) when every row in firstRow..lastRow was exposed with the LED on (off) the
  /// whole time, guard included; else Mixed.
  State stateOver(int firstRow, int lastRow) const;
  /// \brief The fraction of row `row`'s exposure with the LED on (guard not applied).
  double onFraction(int row) const;
};

/// \brief "on", "off" or "mixed".
const char* toString(LedExposure::State state);

}  // namespace slicecap::hal
