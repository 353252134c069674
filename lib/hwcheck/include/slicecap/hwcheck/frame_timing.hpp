// Frame period, jitter and dropped frames from the frames' own timestamps and sequence numbers.
#pragma once

#include <vector>

#include "slicecap/hwcheck/check_report.hpp"
#include "slicecap/hwcheck/check_rig.hpp"

namespace slicecap::hwcheck {

struct FrameTiming {
  bool hasTimestamps = false;  ///< false: every timestamp 0 or not increasing
  double periodUs = 0.0;       ///< median timestamp step per sequence step
  double jitterUs = 0.0;       ///< RMS of each step's difference from period x sequence step
  int dropped = 0;             ///< sequence gaps
  int frames = 0;
  /// Least time from a frame's timestamp to its arrival (the loop's own delays only add).
  double timestampToArrivalUs = 0.0;
};

/// \brief Measures `frames` (in arrival order). Needs at least 3 frames, else hasTimestamps is
/// false and periodUs 0.
FrameTiming measureFrameTiming(const std::vector<SeenFrame>& frames);

/// \brief The report item: fail without timestamps (naming the camera), warn on jitter over
/// 5 % of the period or drops over 2 % of the frames, fail over 20 %.
CheckItem frameTimingItem(const FrameTiming& timing, const std::string& cameraId);

}  // namespace slicecap::hwcheck
