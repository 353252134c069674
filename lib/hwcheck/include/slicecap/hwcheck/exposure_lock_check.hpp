// Whether an exposure lock takes effect, and after how many frames.
#pragma once

#include <optional>

#include "slicecap/hwcheck/check_report.hpp"
#include "slicecap/hwcheck/check_rig.hpp"
#include "slicecap/hwcheck/white_rows.hpp"

namespace slicecap::hwcheck {

struct ExposureLockResult {
  bool refused = false;  ///< the camera refused the lock (reason in `note`)
  double fromUs = 0.0, toUs = 0.0;
  /// Frames that started (timestamp after the lock call) before the first one reporting the new
  /// exposure: 0 means the very next frame to start had it.
  std::optional<int> metadataDelayFrames;
  /// The same, for the first frame whose brightness moved at least a third of the way (in log)
  /// to what the exposure change predicts.
  std::optional<int> brightnessDelayFrames;
  bool reportsExposure = false;  ///< frames carry a non-zero exposure
  std::string note;
};

/// \brief Locks half the current exposure (the current gain) and watches up to `maxFrames`
/// frames: their reported exposure and the brightness of the white references (`whites`; the
/// whole frame when null, or when they are clipped before the lock). Throws what CheckRig throws (no frames, stream ended).
ExposureLockResult checkExposureLock(CheckRig& rig, const WhiteRows* whites, int maxFrames = 15);

CheckItem exposureLockItem(const ExposureLockResult& result, const std::string& cameraId);

}  // namespace slicecap::hwcheck
