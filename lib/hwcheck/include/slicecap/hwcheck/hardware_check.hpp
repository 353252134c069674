// `slicecapd --check-hardware`: every measurement in turn on one camera and LED, into a report.
#pragma once

#include <string>
#include <vector>

#include "slicecap/capture/response_curve.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led.hpp"
#include "slicecap/hwcheck/check_report.hpp"
#include "slicecap/hwcheck/led_timing.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::hwcheck {

/// \brief What the backend says about itself: the caller knows which backend it opened.
struct BackendInfo {
  std::vector<std::string> cameras;  ///< cameras, with their formats and modes, the backend lists
  Verdict rawVerdict = Verdict::Warn;
  std::string rawFinding;  ///< what RAW (Bayer) stream the backend offers
  std::string rawAdvice;
};

struct HardwareCheckOptions {
  double captureSeconds = 2.0;  ///< the frame timing's capture
  LedTimingParams led;
  capture::BracketPlan bracket;
};

/// \brief Configures and starts `camera` with `config`, runs every check with `led` (left off at
/// the end) and stops the camera. Never throws for what the hardware does: a camera that fails
/// to configure, start or deliver, a target not in view, an LED not seen are items with a
/// verdict naming the camera and what to configure; later items that depend on an earlier
/// one say so. `cameraModel` is scaled to the size configure settles on (a binned RAW stream
/// delivers half its sensor mode); another aspect ratio is a failed item. The RAW item is the
/// stream the camera delivers when configure took one, else the backend's finding.
HardwareReport runHardwareCheck(hal::Camera& camera, hal::CameraConfig config, hal::Led& led,
                                hal::Clock& clock, const vision::TargetGeometry& target,
                                const vision::CameraModel& cameraModel, const BackendInfo& backend,
                                const HardwareCheckOptions& options = {});

/// \brief The `led_guard_us` that covers an LED offset and the fit's spread: |offset| + 3 x the
/// residual + 50 us, rounded up to 10 us, at least the default 200 us.
double guardFor(double offsetUs, double residualUs);

/// \brief Writes `text` to `path` atomically (a temporary file in the same folder, flushed, then
/// linked or renamed into place). An existing `path` is kept unless `overwrite`. Throws
/// HardwareCheckError naming the path: it exists, the folder is not writable, the disk is full.
void writeConfigFile(const std::string& path, const std::string& text, bool overwrite);

}  // namespace slicecap::hwcheck
