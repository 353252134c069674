// Where between two LED-off frames an LED-on frame's room light lies (private to lib/capture).
#pragma once

#include <cstdint>
#include <optional>

#include "slicecap/vision/pose.hpp"

namespace slicecap::capture {

/// \brief A frame's time (hal::FrameMetadata::timestampUs) and its pose when it was located.
struct TimedPlace {
  std::int64_t timeUs = 0;
  std::optional<vision::Pose> pose;
};

/// \brief Camera centres closer than this are one place for roomLightWeight: the pose's own
/// noise (a few tenths of a millimetre at 300 mm) would otherwise pick the weight.
inline constexpr double kSamePlaceMm = 2.0;

/// \brief The weight of `after`'s room light for a frame at `at` between LED-off frames `before`
/// and `after` (before's is 1 minus it), in 0..1: `at`'s camera centre projected on the segment
/// from before's to after's, when all three are located and those two are at least kSamePlaceMm
/// apart; else linear in time (0.5 for equal times).
double roomLightWeight(const TimedPlace& before, const TimedPlace& after, const TimedPlace& at);

/// \brief How far apart in place an LED-on frame at `at` and its two LED-off frames were
/// (FrameOutcome::Measurement::roomLightApartMm, roomLightNearestMm): each figure only when the
/// poses it needs are known.
struct RoomLightSpan {
  std::optional<double> apartMm;    ///< the two LED-off frames' camera centres
  std::optional<double> nearestMm;  ///< `at`'s camera centre from the nearer of theirs
};
RoomLightSpan roomLightSpan(const std::optional<vision::Pose>& before,
                            const std::optional<vision::Pose>& after, const vision::Pose& at);

}  // namespace slicecap::capture
