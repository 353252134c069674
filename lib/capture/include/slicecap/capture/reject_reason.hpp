// Why the capture pipeline rejected a frame: one enumerator per reason, with the stable snake_case
// name the status, the reports and the journal count it under.
#pragma once

#include <optional>
#include <ostream>
#include <string_view>

namespace slicecap::capture {

/// \brief "detection_deferred": too few markers found within the frame's detection budget
/// (MarkerDetectorSettings::frameBudgetPx) while the search wanted more (a wider region, the
/// next re-acquisition passes), which go on in the next frames; "too_few_markers": the frame's
/// whole planned search ran and found too few; "led_transition": the LED switched while the rows
/// of the window or the white references were exposed (neither a sample nor room light);
/// "room_light_unseen": the room light changes along the camera's path and neither LED-off frame
/// was taken where the LED-on frame was (PipelineSettings::maxRoomLightDistanceMm).
// In the alphabetical order of their names: counts kept by reason list in the order they always
// did when the reasons were strings.
enum class RejectReason {
  BadFrame,
  Blurred,
  DetectionDeferred,
  ElevationOff,
  LedTransition,
  NoAmbientFrame,
  PoseResidual,
  RoomLightUnseen,
  TooFewMarkers,
  WindowClipped,
  WindowOccluded,
};

/// \brief Every reason, in the order of the enumeration.
inline constexpr RejectReason kRejectReasons[] = {
    RejectReason::BadFrame,      RejectReason::Blurred,       RejectReason::DetectionDeferred,
    RejectReason::ElevationOff,  RejectReason::LedTransition, RejectReason::NoAmbientFrame,
    RejectReason::PoseResidual,  RejectReason::RoomLightUnseen, RejectReason::TooFewMarkers,
    RejectReason::WindowClipped, RejectReason::WindowOccluded};

/// \brief The reason's stable name, e.g. "window_occluded".
std::string_view toString(RejectReason reason);

/// \brief The reason of a stable name; none for a name that is not one.
std::optional<RejectReason> parseRejectReason(std::string_view name);

inline std::ostream& operator<<(std::ostream& out, RejectReason reason) {
  return out << toString(reason);
}

}  // namespace slicecap::capture
