// What the real backends send for a pinned frame duration (slicecapd.conf mains_hz,
// CameraConfig::frameDurationUs) and how they keep the exposure inside it: libcamera's
// FrameDurationLimits, V4L2's frame interval and power-line-frequency control. Pure decisions,
// tested on their own; libcamera_*.cpp and v4l2_*.cpp only apply them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace slicecap::hal {

/// \brief The frame durations a camera lists for FrameDurationLimits (its sensor mode's range;
/// the Raspberry Pi IPA sets it after configure, ipa_base.cpp), in microseconds.
struct FrameDurationRange {
  std::int64_t minUs = 0;
  std::int64_t maxUs = 0;
};

/// \brief The frame duration to ask for: `limitsUs` is sent as FrameDurationLimits = {d, d}
/// (nullopt: nothing is sent), and `grantedUs` is what the frames will run at as far as the
/// camera's listed range says (nullopt: unknown, the camera's own). `notes` says each change.
struct FrameDurationPlan {
  std::optional<std::int64_t> limitsUs;
  std::optional<double> grantedUs;
  std::vector<std::string> notes;
};

/// \brief The plan for `wantedUs` (nullopt: not pinned, nothing sent, no note) on a camera that
/// lists `listed` (nullopt: it lacks FrameDurationLimits: nothing sent, said). The wanted
/// duration is rounded to whole microseconds (the control's unit; 33333.3 us at 60 Hz drifts
/// 0.3 us a frame) and clamped into the listed range (the IPA would clamp it the same way,
/// ipa_base.cpp applyFrameDurations), each said.
FrameDurationPlan planFrameDuration(std::optional<double> wantedUs,
                                    std::optional<FrameDurationRange> listed);

/// \brief An exposure held inside a pinned frame: `exposureUs` is at most the frame duration,
/// `note` is set when it was shortened.
struct ExposureInFrame {
  double exposureUs = 0.0;
  std::optional<std::string> note;
};

/// \brief Clamps `exposureUs` to `frameDurationUs` (nullopt: no limit). Asked for longer than
/// the frame, a sensor cannot expose it: the Raspberry Pi IPA clamps a fixed exposure to the
/// longest the maximum frame duration allows (ipa_base.cpp applyFrameDurations ->
/// agc_channel.cpp limitExposureTime), a few lines shorter still (the sensor's
/// frameIntegrationDiff, cam_helper.cpp getBlanking). slicecap clamps, says so, and reads each
/// frame's own ExposureTime, which says what ran: refusing would end the sweep's metering for an
/// exposure the frame cannot hold anyway.
ExposureInFrame clampExposureToFrame(double exposureUs, std::optional<double> frameDurationUs);

/// \brief A V4L2 frame interval (struct v4l2_fract timeperframe), in seconds as a fraction.
struct TimePerFrame {
  std::uint32_t numerator = 0;
  std::uint32_t denominator = 1;
};

/// \brief The frame interval of `frameDurationUs`: microseconds over 1000000, reduced
/// (40000 us -> 1/25). Throws CameraError naming the value for a duration that is not positive
/// or does not fit a 32-bit numerator.
TimePerFrame timePerFrameOf(double frameDurationUs);

/// \brief The frame duration in microseconds of a frame interval a driver granted; nullopt for
/// a zero numerator or denominator (the driver said nothing usable).
std::optional<double> frameDurationUsOf(TimePerFrame interval);

/// \brief The V4L2_CID_POWER_LINE_FREQUENCY menu value for the mains (videodev2.h: 0 disabled,
/// 1 50 Hz, 2 60 Hz): 50 and 60 as such, 0 disabled. Throws CameraError naming any other.
std::int32_t powerLineFrequencyMenuValue(int mainsHz);

}  // namespace slicecap::hal
