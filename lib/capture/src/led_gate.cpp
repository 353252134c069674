// The rows a sample reads, and the LED's state over them.
#include "slicecap/capture/led_gate.hpp"

#include <algorithm>
#include <cmath>

namespace slicecap::capture {

RowSpan rowsOfInterest(const vision::TargetGeometry& target, const vision::CameraModel& camera,
                       const vision::Pose& pose, int heightPx, double marginPx) {
  const RowSpan whole{0, std::max(0, heightPx - 1)};
  double top = 1e30, bottom = -1e30;
  const auto add = [&](const vision::RectMm& rect) {
    for (const double x : {rect.xMinMm, rect.xMaxMm})
      for (const double y : {rect.yMinMm, rect.yMaxMm}) {
        const auto px = camera.project(pose.toCamera({x, y, 0.0}));
        if (!px) return false;
        top = std::min(top, px->y());
        bottom = std::max(bottom, px->y());
      }
    return true;
  };
  if (!add(target.window)) return whole;
  for (const vision::Patch& patch : target.patches)
    if (patch.kind == vision::PatchKind::White && !add(patch.rect)) return whole;
  RowSpan span;
  span.first = std::clamp(static_cast<int>(std::floor(top - marginPx)), 0, whole.last);
  span.last = std::clamp(static_cast<int>(std::ceil(bottom + marginPx)), 0, whole.last);
  return span;
}

hal::LedExposure::State ledStateOver(const hal::Frame& frame, RowSpan rows) {
  if (!frame.metadata.ledExposure)
    return frame.metadata.ledOn ? hal::LedExposure::State::On : hal::LedExposure::State::Off;
  return frame.metadata.ledExposure->stateOver(rows.first, rows.last);
}

}  // namespace slicecap::capture
