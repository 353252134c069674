// The V4L2 camera's controls: exposure and gain set manually and clamped to the device's ranges,
// the controls as they were kept to put back, and the exposure lock of a running sweep.
#include <cmath>
#include <stdexcept>

#include "slicecap/hal/frame_timing.hpp"
#include "v4l2_state.hpp"

namespace slicecap::hal {

using namespace v4l2_parts;

std::optional<v4l2_queryctrl> V4l2Camera::State::queryControl(std::uint32_t id) const {
  v4l2_queryctrl query{};
  query.id = id;
  if (retryIoctl(fd, VIDIOC_QUERYCTRL, &query) != 0) return std::nullopt;
  if ((query.flags & V4L2_CTRL_FLAG_DISABLED) != 0) return std::nullopt;
  return query;
}

std::optional<std::int32_t> V4l2Camera::State::getControl(std::uint32_t id) const {
  v4l2_control control{};
  control.id = id;
  if (retryIoctl(fd, VIDIOC_G_CTRL, &control) != 0) return std::nullopt;
  return control.value;
}

/// The exposure and gain controls as they are, to put back: the modes first, then a value only
/// where its mode leaves it to the user (an auto mode owns its value; shutter priority keeps
/// the exposure time manual).
std::vector<std::pair<std::uint32_t, std::int32_t>> V4l2Camera::State::exposureControls() const {
  const std::optional<std::int32_t> autoExposure = getControl(V4L2_CID_EXPOSURE_AUTO);
  const std::optional<std::int32_t> autoGain = getControl(V4L2_CID_AUTOGAIN);
  std::vector<std::pair<std::uint32_t, std::int32_t>> controls;
  if (autoExposure) controls.emplace_back(V4L2_CID_EXPOSURE_AUTO, *autoExposure);
  if (autoGain) controls.emplace_back(V4L2_CID_AUTOGAIN, *autoGain);
  const std::int32_t exposureMode = autoExposure.value_or(V4L2_EXPOSURE_MANUAL);
  if (exposureMode == V4L2_EXPOSURE_MANUAL || exposureMode == V4L2_EXPOSURE_SHUTTER_PRIORITY)
    if (const std::optional<std::int32_t> v = getControl(V4L2_CID_EXPOSURE_ABSOLUTE))
      controls.emplace_back(V4L2_CID_EXPOSURE_ABSOLUTE, *v);
  if (autoGain.value_or(0) == 0)
    if (const std::optional<std::int32_t> v = getControl(V4L2_CID_GAIN))
      controls.emplace_back(V4L2_CID_GAIN, *v);
  return controls;
}

bool V4l2Camera::State::setControl(std::uint32_t id, std::int32_t value) const {
  v4l2_control control{};
  control.id = id;
  control.value = value;
  return retryIoctl(fd, VIDIOC_S_CTRL, &control) == 0;
}

/// Sets a control to `wanted` clamped and stepped to its range; returns the value set, or
/// nullopt when the device lacks the control or refuses it.
std::optional<std::int32_t> V4l2Camera::State::setRangedControl(std::uint32_t id, double wanted) const {
  const std::optional<v4l2_queryctrl> query = queryControl(id);
  if (!query) return std::nullopt;
  const double step = query->step > 0 ? query->step : 1;
  double value = std::round((wanted - query->minimum) / step) * step + query->minimum;
  value = std::min<double>(std::max<double>(value, query->minimum), query->maximum);
  const auto set = static_cast<std::int32_t>(value);
  if (!setControl(id, set)) return std::nullopt;
  return set;
}

/// Auto exposure off and the exposure set, clamped to the control's range; returns the
/// exposure set in microseconds (V4L2_CID_EXPOSURE_ABSOLUTE counts 100 us), or nullopt when the
/// device has no manual exposure.
std::optional<double> V4l2Camera::State::setManualExposureUs(double wantedUs) const {
  setControl(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL);
  const std::optional<std::int32_t> set =
      setRangedControl(V4L2_CID_EXPOSURE_ABSOLUTE, wantedUs / 100.0);
  if (!set) return std::nullopt;
  return *set * 100.0;
}

/// Auto gain off and the gain set (the device's own units), clamped to its range; returns the
/// gain set, or nullopt when the device lacks the control or refuses it.
std::optional<std::int32_t> V4l2Camera::State::setManualGain(double wanted) const {
  setControl(V4L2_CID_AUTOGAIN, 0);
  return setRangedControl(V4L2_CID_GAIN, wanted);
}

void V4l2Camera::State::setPowerLineFrequency(int mainsHz, std::string& said) const {
  if (!queryControl(V4L2_CID_POWER_LINE_FREQUENCY)) return;
  setControl(V4L2_CID_POWER_LINE_FREQUENCY, powerLineFrequencyMenuValue(mainsHz));
  const std::optional<std::int32_t> readBack = getControl(V4L2_CID_POWER_LINE_FREQUENCY);
  static constexpr const char* kNames[] = {"disabled", "50 Hz", "60 Hz", "auto"};
  said += std::string(said.empty() ? "" : ", ") + "power line frequency " +
          (readBack && *readBack >= 0 && *readBack <= 3 ? kNames[*readBack]
                                                         : std::string("unreadable"));
}

ExposureLock V4l2Camera::lockExposure(const ExposureSetting& wanted) {
  if (!state_->streaming) throw std::logic_error("V4l2Camera::lockExposure before start");
  // A lock the device refuses halfway (e.g. the gain after the exposure) is undone: a fixed
  // exposure that neither the frames nor the status report would be worse than none.
  const std::vector<std::pair<std::uint32_t, std::int32_t>> before = state_->exposureControls();
  auto refuse = [&](const std::string& reason) -> ExposureLock {
    for (const auto& [id, value] : before)
      state_->setControl(id, value);
    return {std::nullopt, reason};
  };
  // Inside the pinned frame interval: a sensor cannot expose longer than its frame.
  const double inFrameUs =
      clampExposureToFrame(wanted.exposureUs, state_->config.frameDurationUs).exposureUs;
  const std::optional<double> exposureUs = state_->setManualExposureUs(inFrameUs);
  if (!exposureUs) return refuse(state_->device + " has no manual exposure");
  // Auto gain off too, or it would undo the metering; a camera without a gain control is unity.
  double gain = 1.0;
  if (const std::optional<v4l2_queryctrl> query = state_->queryControl(V4L2_CID_GAIN)) {
    const std::optional<std::int32_t> set =
        state_->setManualGain(wanted.gain.value_or(query->default_value));
    if (!set) return refuse(state_->device + " refused a manual gain");
    gain = *set;
  } else {
    state_->setControl(V4L2_CID_AUTOGAIN, 0);
  }
  if (state_->locks == 0) {
    state_->controlsBeforeLocks = before;
    state_->exposureUsBeforeLocks = state_->config.exposureUs;
    state_->gainBeforeLocks = state_->config.gain;
  }
  ++state_->locks;
  state_->exposureBeforeLockUs = state_->config.exposureUs.value_or(0.0);
  state_->gainBeforeLock = state_->config.gain.value_or(1.0);
  state_->lockReachesFrame = state_->dequeued + state_->grantedBuffers + 1;
  state_->config.exposureUs = *exposureUs;
  state_->config.gain = gain;
  return {ExposureSetting{*exposureUs, gain}, ""};
}

}  // namespace slicecap::hal
