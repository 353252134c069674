// A live sweep's HDR (slicecapd.conf hdr_levels): when its cycle starts, each frame's level, the
// exposure switched with the LED pairs, the shortest level shortened where it clips, the status.
#pragma once

#include <optional>
#include <string>

#include "slicecap/daemon/hdr_cycle.hpp"
#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/control/reply_views.hpp"
#include "slicecap/hal/camera.hpp"

namespace slicecap::daemon {

/// \brief The daemon's side of a live HDR sweep, between its frame loop and HdrCycle. A camera
/// that cannot lock or switch its exposure leaves the sweep at one exposure, said in the status.
/// Single-threaded (the event loop); nothing here throws.
class SweepHdr {
 public:
  /// \brief `levels`: hdr_levels (1: this does nothing).
  explicit SweepHdr(int levels) : levels_(levels) {}

  /// \brief A sweep run starts: the last run's line is not this one's.
  void reset();
  /// \brief The camera stopped: the cycle ends, its line stays for the status.
  void stop();
  /// \brief Once the sweep's exposure is known (after the metering and the bracket), on a live
  /// camera: starts the cycle from `locked` (nullopt: the camera's auto exposure runs).
  void start(const std::string& cameraId, const std::optional<hal::ExposureSetting>& locked);
  bool started() const { return cycle_.has_value() || !note_.empty(); }
  /// \brief Labels a live frame with the level it was taken at (nothing without a cycle).
  void label(hal::Frame& frame) const;
  /// \brief The LED switched on: a new pair, which may switch the camera to the next level.
  void pairStarted(hal::Camera& camera);
  /// \brief After the pipeline: the shortest level's clipped window shortens it.
  void noteOutcome(const hal::FrameMetadata& frame, const capture::FrameOutcome& outcome);
  /// \brief The status's "hdr" line, when hdr_levels asked for HDR.
  void describe(control::StatusView& status) const;

 private:
  int levels_;
  std::optional<HdrCycle> cycle_;
  std::string note_;
};

}  // namespace slicecap::daemon
