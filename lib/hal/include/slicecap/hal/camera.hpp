// The camera interface every source implements: libcamera, V4L2 (the daemon) and the file camera.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slicecap/core/pixel_encoding.hpp"
#include "slicecap/hal/frame.hpp"

namespace slicecap::hal {

/// \brief Whether a camera delivers its sensor's RAW (Bayer) samples, decoded to linear light
/// (hal::decodeBayer: black level off, 2 x 2 binned, half the sensor mode's size): Auto takes RAW
/// when the camera offers a format slicecap decodes, else the processed stream; On refuses a
/// camera without one (ConfigResult::Invalid); Off always takes the processed stream.
enum class RawCapture { Auto, On, Off };

/// \brief "auto", "on" or "off" (slicecapd.conf's camera_raw).
inline std::string_view toString(RawCapture raw) {
  return raw == RawCapture::On ? "on" : raw == RawCapture::Off ? "off" : "auto";
}
/// \brief The setting spelled exactly "auto", "on" or "off", or nullopt.
inline std::optional<RawCapture> parseRawCapture(std::string_view text) {
  if (text == "auto") return RawCapture::Auto;
  if (text == "on") return RawCapture::On;
  if (text == "off") return RawCapture::Off;
  return std::nullopt;
}

/// \brief What the session asks for. Exposure and gain are locked when set (the capture needs
/// frames whose brightness it can relate); nullopt leaves them to the camera.
struct CameraConfig {
  int widthPx = 1280;
  int heightPx = 720;
  PixelEncoding encoding = PixelEncoding::Srgb8;
  std::optional<double> exposureUs;
  std::optional<double> gain;
  int bufferCount = 4;  ///< frames the source may queue ahead
  RawCapture raw = RawCapture::Auto;
  /// The sensor's top-to-bottom readout time, when known (slicecapd.conf readout_us): a V4L2
  /// camera whose timestamps mark the end of a frame needs it to say when the frame began.
  std::optional<double> readoutUs{};
  /// The frame duration to hold every frame at (slicecapd.conf mains_hz: a whole number of the
  /// room light's flicker periods, hal::frameDurationUsForMains); nullopt: the camera's own. A
  /// camera that cannot hold it says so in its ConfigResult (Adjusted, with the duration it runs
  /// at written back here). libcamera: FrameDurationLimits = {this, this}; V4L2: the frame
  /// interval (VIDIOC_S_PARM). An exposure longer than it is clamped to it and said
  /// (hal::clampExposureToFrame).
  std::optional<double> frameDurationUs{};
  /// The room lights' mains frequency (slicecapd.conf mains_hz: 50, 60, or 0 for none); nullopt:
  /// not said. V4L2 sets V4L2_CID_POWER_LINE_FREQUENCY from it where the device has the control.
  std::optional<int> mainsHz{};
  /// Set by configure: the RAW format the frames are decoded from (libcamera's name, e.g.
  /// "SRGGB10_CSI2P"); empty when they come from the processed stream.
  std::string rawFormat{};
};

/// \brief The outcome of Camera::configure, as libcamera's CameraConfiguration::validate: Valid
/// (taken as asked), Adjusted (the config was changed to what the source can do; read it back),
/// Invalid (nothing usable; `reason` says why).
struct ConfigResult {
  enum class Status { Valid, Adjusted, Invalid };
  Status status = Status::Valid;
  std::string reason;  ///< what was adjusted, or why it is invalid

  /// \brief Valid when nothing was adjusted, else Adjusted with the adjustments joined by "; ".
  static ConfigResult fromAdjustments(const std::vector<std::string>& adjustments) {
    if (adjustments.empty()) return {Status::Valid, ""};
    std::string joined;
    for (const std::string& adjustment : adjustments)
      joined += (joined.empty() ? "" : "; ") + adjustment;
    return {Status::Adjusted, joined};
  }
};

/// \brief The outcome of waiting for a frame. Expected outcomes are values, not exceptions:
/// EndOfStream (a file camera played its last frame), Timeout, Error (the device failed; the
/// session pauses the sweep and reports `error`).
struct CaptureResult {
  enum class Status { Frame, EndOfStream, Timeout, Error };
  Status status = Status::Frame;
  std::optional<Frame> frame;  ///< set exactly when status is Frame
  std::string error;
};

/// \brief An exposure to fix while a camera runs (Camera::lockExposure).
struct ExposureSetting {
  double exposureUs = 0.0;
  std::optional<double> gain;  ///< in the source's own units; nullopt asks for its default gain
};

/// \brief What Camera::lockExposure did: `locked` is what is now fixed (clamped to the source's
/// range, the gain filled in), or empty with `reason` saying why the source keeps its own.
struct ExposureLock {
  std::optional<ExposureSetting> locked;
  std::string reason;
};

/// \brief A frame source. Call order: configure, start, nextFrame..., stop (start again is
/// allowed). Calls out of order throw std::logic_error. One instance per device; implementations
/// share one libcamera CameraManager per process among themselves (issue 6).
class Camera {
 public:
  virtual ~Camera() = default;
  /// \brief A human-readable id, e.g. the recording's path or the sensor's name.
  virtual std::string id() const = 0;
  /// \brief Validates `config` and adjusts it in place to what the source can deliver.
  virtual ConfigResult configure(CameraConfig& config) = 0;
  virtual void start() = 0;
  virtual void stop() = 0;
  /// \brief The next frame, waiting at most `timeout` for it.
  virtual CaptureResult nextFrame(std::chrono::milliseconds timeout) = 0;
  /// \brief A descriptor that becomes readable when a frame is ready, for the daemon's poll loop;
  /// nullopt when frames are always ready at once (the file camera).
  virtual std::optional<int> readyDescriptor() const { return std::nullopt; }
  /// \brief Between start and stop: fixes exposure and gain for the frames that follow (a few
  /// frames late: controls take that long to reach the sensor), for the daemon's metering at
  /// sweep start. Frames then report the locked values in their metadata once they were exposed
  /// with them, and the exposure before the lock until then (0: auto exposure), so that a frame
  /// says which exposure it had. A lock the source cannot make is refused as a whole (`locked`
  /// empty): the source is left as it was. Throws CameraError when the device fails,
  /// std::logic_error outside start..stop. This default: the source cannot (a recording's
  /// exposure is what it was).
  virtual ExposureLock lockExposure(const ExposureSetting& /*wanted*/) {
    return {std::nullopt, "this source cannot change its exposure"};
  }
};

}  // namespace slicecap::hal
