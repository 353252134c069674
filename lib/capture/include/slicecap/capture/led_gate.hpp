// Which LED state a frame's sample rows were exposed under: the gate against rolling-shutter
// frames half lit by an LED switch.
#pragma once

#include <optional>

#include "slicecap/hal/frame.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::capture {

/// \brief Image rows first..last (inclusive).
struct RowSpan {
  int first = 0;
  int last = 0;
};

/// \brief The rows holding the window and the white references seen from `pose`, grown by
/// `marginPx` (the hand's motion to the next frame, blur), clamped to the frame; the whole frame
/// when a corner does not project.
RowSpan rowsOfInterest(const vision::TargetGeometry& target, const vision::CameraModel& camera,
                       const vision::Pose& pose, int heightPx, double marginPx);

/// \brief The LED's state over `rows` of `frame`: from its LED exposure when the frame has one
/// (On, Off or Mixed), else its `ledOn` label (a recording, an offline run).
hal::LedExposure::State ledStateOver(const hal::Frame& frame, RowSpan rows);

}  // namespace slicecap::capture
