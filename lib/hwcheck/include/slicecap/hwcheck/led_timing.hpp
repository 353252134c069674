// The LED-to-frame timing and the rolling shutter's line time: switch the LED at known times and
// find in which frame, and from which row, the white references change.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/linear_view.hpp"
#include "slicecap/hwcheck/check_report.hpp"
#include "slicecap/hwcheck/check_rig.hpp"
#include "slicecap/hwcheck/white_rows.hpp"

namespace slicecap::hwcheck {

struct LedTimingParams {
  /// Short, so that a switch blurs over few rows (exposure / line time: 25 rows at 1 ms on a
  /// 40 us line); the gain makes up the light.
  double exposureUs = 1000.0;
  /// Switches, each at another phase of the frame period: the white references cover a part of
  /// the rows, so only some switches land where they can be seen.
  int switches = 32;
  /// Then switches aimed, from the first pass's fit, at rows spread over the white references.
  int aimedSwitches = 24;
  /// Frames averaged for each row's LED-on and LED-off reference.
  int referenceFrames = 6;
};

/// \brief One switch seen in a frame's white rows.
struct LedTransition {
  double switchUs = 0.0;     ///< the switch's recorded time
  double halfRow = 0.0;      ///< the row exposed half before, half after it
  double sinceRow0Us = 0.0;  ///< switch - (row 0's exposure start + exposure / 2)
  int frameShift = 0;        ///< the frame it showed in minus the frame it was aimed at
};

struct LedTiming {
  int switchesMade = 0;
  /// Rows whose white references the LED changes by more than 5 % (0: the LED is not seen).
  int respondingRows = 0;
  std::vector<LedTransition> transitions;
  std::optional<double> lineTimeUs, readoutUs;
  /// The light's change after the recorded switch, on the frames' clock (>0: later).
  std::optional<double> offsetUs;
  std::optional<double> residualUs;  ///< RMS of the fit's residuals
  std::optional<int> frameShift;     ///< the most common frameShift
  std::string problem;               ///< why nothing could be measured
};

/// \brief Locks params.exposureUs (gain = brightExposureUs over it, capped at 16), takes LED-on
/// and LED-off reference frames, then switches the LED once every other frame at spread phases
/// and fits each seen switch's half-lit row against its time: time = line time x row - offset;
/// then aims params.aimedSwitches more at rows spread over the whites and fits them all.
/// `codes` decodes the frames (the measured curve, so that "half lit" is half the light).
/// Frames without an exposure start (exposureStartUs) give `problem`, as does an LED the white
/// rows do not see. Throws what CheckRig throws.
LedTiming measureLedTiming(CheckRig& rig, const WhiteRows& whites, const capture::CodeTable& codes,
                           double framePeriodUs, double brightExposureUs,
                           const LedTimingParams& params = {});

/// \brief Fits `transitions` (at least 3, spread over 20 rows or more): fills lineTimeUs,
/// readoutUs (x heightPx), offsetUs, residualUs, frameShift; else sets `problem`.
void fitLedTiming(LedTiming& timing, int heightPx);

CheckItem ledTimingItem(const LedTiming& timing, const std::string& cameraId);

}  // namespace slicecap::hwcheck
