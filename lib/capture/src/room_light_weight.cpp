// Where between two LED-off frames an LED-on frame's room light lies.
#include "room_light_weight.hpp"

#include <algorithm>

namespace slicecap::capture {

double roomLightWeight(const TimedPlace& before, const TimedPlace& after, const TimedPlace& at) {
  if (before.pose && after.pose && at.pose) {
    const Eigen::Vector3d from = before.pose->cameraCentreMm();
    const Eigen::Vector3d step = after.pose->cameraCentreMm() - from;
    const double length2 = step.squaredNorm();
    if (length2 >= kSamePlaceMm * kSamePlaceMm)
      return std::clamp((at.pose->cameraCentreMm() - from).dot(step) / length2, 0.0, 1.0);
  }
  const double t0 = static_cast<double>(before.timeUs), t1 = static_cast<double>(after.timeUs);
  if (!(t1 > t0)) return 0.5;
  return std::clamp((static_cast<double>(at.timeUs) - t0) / (t1 - t0), 0.0, 1.0);
}

RoomLightSpan roomLightSpan(const std::optional<vision::Pose>& before,
                            const std::optional<vision::Pose>& after, const vision::Pose& at) {
  if (!before || !after) return {};
  const Eigen::Vector3d a = before->cameraCentreMm(), b = after->cameraCentreMm();
  const Eigen::Vector3d here = at.cameraCentreMm();
  return {(b - a).norm(), std::min((here - a).norm(), (here - b).norm())};
}

}  // namespace slicecap::capture
