// What a live sweep run measures before its frames count: the exposure (metering with the LED on)
// and the decoding of its frames (a response bracket where one is taken).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/control/reply_views.hpp"
#include "slicecap/daemon/daemon_parts.hpp"
#include "slicecap/daemon/exposure_meter.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"
#include "slicecap/hal/camera.hpp"

namespace slicecap::daemon {

/// \brief The sweep run's exposure and decoding. While the metering or the bracket runs the LED
/// stays on and no frame reaches the pipeline; then the exposure stays locked for the sweep and
/// the decoding is decided on the first frame after the metering. Runs on the event loop; the
/// camera and LED calls throw std::exception naming their device.
class SweepCalibration {
 public:
  /// \brief `parts` outlives this.
  explicit SweepCalibration(const DaemonParts& parts) : parts_(parts) {}

  /// \brief A new sweep run: the last run's exposure line and decoding are not this one's.
  void reset();
  /// \brief Starts the metering on a live camera without a configured exposure (LED on); a
  /// camera that cannot lock leaves its auto exposure running (a warning).
  void begin(hal::Camera& opened);
  /// \brief The metering's start failed (the camera is stopped): nothing of it is shown.
  void abandonMetering();
  /// \brief The camera stopped: a metering cut short locked nothing final, its "metering ..."
  /// line would outlive it; a bracket cut short decides nothing.
  void cameraStopped();

  bool metering() const { return meter_.has_value(); }
  bool bracketing() const { return bracket_.has_value(); }
  bool decided() const { return decoding_.has_value(); }
  /// \brief The sweep's exposure once the metering locked it (or exposure_us); nullopt while it
  /// is metered, or when the camera's auto exposure runs.
  std::optional<hal::ExposureSetting> lockedSetting() const {
    return exposureUnlocked_ || meter_ ? std::nullopt : lockedSetting_;
  }

  /// \brief One frame of the metering: measured, never processed; the LED stays on.
  void meterFrame(hal::Camera& camera, const hal::Frame& frame);
  /// \brief The first frame after the metering: the sweep's decoding without a bracket (a linear
  /// stream, decoding = srgb, a camera that cannot take one), or nullopt when a bracket started.
  std::optional<SweepDecoding> decide(hal::Camera& camera, const hal::Frame& frame,
                                      const SliceId& slice);
  /// \brief One frame of the bracket: kept or skipped, never processed; the LED stays on. The
  /// decoding once the bracket is done.
  std::optional<SweepDecoding> bracketFrame(hal::Camera& camera, const hal::Frame& frame);
  /// \brief The warning the status shows until the next sweep start.
  void noteDecodingWarning(std::string warning) { decodingWarning_ = std::move(warning); }
  /// \brief The decoding the sweep's frames are read through from now on.
  void adopt(SweepDecoding decided) { decoding_ = std::move(decided); }

  /// \brief The status's "exposure" (or, when the camera could not lock, a warning).
  void describeExposure(control::StatusView& status) const;
  /// \brief The status's "decoding" and the decoding's warning.
  void describeDecoding(control::StatusView& status) const;

 private:
  void leaveExposureToCamera(const std::string& cameraId, const std::string& reason);
  SweepDecoding finishBracket(const std::string& cameraId);

  const DaemonParts& parts_;
  std::optional<ExposureMeter> meter_;
  // What the metering did, or why the camera's auto exposure runs instead (then also a warning).
  std::string exposureNote_;
  bool exposureUnlocked_ = false;
  std::uint32_t locksAccepted_ = 0;  // the camera's locks since it started
  std::optional<hal::ExposureSetting> lockedSetting_;  // the sweep's exposure, once known
  std::optional<ResponseBracket> bracket_;
  std::optional<BracketSubject> subject_;  // what the bracket is fitted against
  std::optional<SweepDecoding> decoding_;
  std::string decodingWarning_;  // shown by every status until the next sweep start
};

}  // namespace slicecap::daemon
