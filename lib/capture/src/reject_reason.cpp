// The reject reasons' stable names (a table, as libcamera names its enumerations' values).
#include "slicecap/capture/reject_reason.hpp"

#include <array>
#include <utility>

namespace slicecap::capture {
namespace {

constexpr std::array<std::pair<RejectReason, std::string_view>, std::size(kRejectReasons)> kNames{{
    {RejectReason::TooFewMarkers, "too_few_markers"},
    {RejectReason::DetectionDeferred, "detection_deferred"},
    {RejectReason::ElevationOff, "elevation_off"},
    {RejectReason::Blurred, "blurred"},
    {RejectReason::WindowClipped, "window_clipped"},
    {RejectReason::WindowOccluded, "window_occluded"},
    {RejectReason::PoseResidual, "pose_residual"},
    {RejectReason::NoAmbientFrame, "no_ambient_frame"},
    {RejectReason::RoomLightUnseen, "room_light_unseen"},
    {RejectReason::BadFrame, "bad_frame"},
    {RejectReason::LedTransition, "led_transition"},
}};

}  // namespace

std::string_view toString(RejectReason reason) {
  for (const auto& [r, name] : kNames)
    if (r == reason) return name;
  return "unknown";
}

std::optional<RejectReason> parseRejectReason(std::string_view name) {
  for (const auto& [r, n] : kNames)
    if (n == name) return r;
  return std::nullopt;
}

}  // namespace slicecap::capture
