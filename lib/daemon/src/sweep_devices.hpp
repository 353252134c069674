// The devices of the running sweep: its camera (open, stop, frames pumped through the pipeline
// into the session), the LED's strobe, the calibration and HDR of a live camera, and what the
// sweep keeps besides its samples; all kept in line with the session manager's sweep.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "slicecap/control/reply_views.hpp"
#include "slicecap/daemon/daemon_parts.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/daemon/decoding_watch.hpp"
#include "slicecap/daemon/room_light_watch.hpp"
#include "slicecap/daemon/session_manager.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "sweep_calibration.hpp"
#include "sweep_hdr.hpp"
#include "sweep_outputs.hpp"
#include "sweep_strobe.hpp"

namespace slicecap::daemon {

/// \brief The sweep's devices on the event loop. The LED is on only while the sweep captures.
/// Where a device fails, the sweep pauses with the device's message and the devices follow
/// (reconcile): nothing here throws out of a frame.
///
/// Its jobs are one file each: sweep_devices.cpp opens, stops and follows the session;
/// sweep_frames.cpp pumps a frame through calibration, strobe and pipeline into the session;
/// sweep_strobe.cpp, sweep_calibration.cpp, sweep_hdr.cpp and sweep_outputs.cpp hold the parts.
class SweepDevices {
 public:
  /// \brief `parts`, `loop`, `manager` and `clock` outlive this; parts.led records its switches on
  /// `commanded` (hal::TimelineLed), which the strobe labels frames from.
  SweepDevices(DaemonParts& parts, EventLoop& loop, SessionManager& manager, hal::Clock& clock,
               std::shared_ptr<hal::LedTimeline> commanded);
  ~SweepDevices();
  SweepDevices(const SweepDevices&) = delete;
  SweepDevices& operator=(const SweepDevices&) = delete;

  /// \brief Brings the devices in line with the session state after anything that may change it:
  /// the swept slice's texture and recorder, its camera started or stopped, the LED off unless
  /// the sweep captures.
  void reconcile();
  /// \brief Stops the camera (its strobe and HDR) and switches the LED off.
  void stopCamera();
  /// \brief Switches the LED off; a failure is logged, not thrown.
  void ledOff() noexcept;
  /// \brief The frames the pipeline holds, settled as the stream ends or the sweep stops (before
  /// the sweep pauses, so their samples count).
  void settleHeld();

  /// \brief What the sweep keeps besides its samples (a redo discards it; a stop reports it).
  SweepOutputs& outputs() { return outputs_; }
  /// \brief The status's parts from the devices: recording, texture, exposure, HDR, the camera's
  /// frames, the decoding, the room light, and the warnings of the configuration, the camera and
  /// the last sweep start, in that order.
  void describe(control::StatusView& status) const;

 private:
  // sweep_devices.cpp
  void startCamera(const SliceId& slice);
  bool openCamera(const SliceId& slice, std::shared_ptr<hal::Camera>& opened);
  void watchCamera();
  // sweep_frames.cpp
  void pumpFrame();
  bool endOfFrames(const hal::CaptureResult& result);
  bool calibrate(const hal::Frame& frame);
  void applyDecoding(SweepDecoding decided);
  void recordDecoding(const SweepDecoding& decided, std::string& warning) const;
  /// The sweep run's decoding check into its decoding record, as the run stops (logged on failure).
  void recordDecodingCheck() const noexcept;
  /// The sweep run's samples refused as it stops, when its decoding check shows them broken;
  /// true when they were set aside (and the run's texture frames with them).
  bool refuseBrokenDecoding();
  void strobe(hal::Frame& frame);
  void apply(const capture::SettledFrame& settled);

  DaemonParts& parts_;
  EventLoop& loop_;
  SessionManager& manager_;

  // The running sweep's camera and pipeline; empty while nothing captures.
  std::shared_ptr<hal::Camera> camera_;
  std::optional<SliceId> cameraSlice_;
  std::optional<std::uint64_t> runFirstRecord_;  ///< the run's first journal record
  bool runRefused_ = false;  ///< the run ended refused (its watch kept for the status)
  capture::LiveFrameProcessor processor_;
  capture::FrameObserver observer_;
  std::optional<int> watchedFd_;
  std::optional<EventLoop::TimerId> pollTimer_;
  // What the camera could not do as configured, as it said at the last start.
  std::string cameraAdjustment_;

  // record_frames and texture capture: what the sweep writes besides its samples.
  SweepOutputs outputs_;
  // Sweep-start metering and the sweep run's decoding (no frame is processed meanwhile).
  SweepCalibration calibration_;
  // A live camera's strobe, from the end of the calibration to the sweep's stop.
  SweepStrobe strobe_;
  // A live HDR sweep (hdr_levels > 1), from the end of the calibration to the sweep's stop.
  SweepHdr hdr_;
  // The room light the sweep run's samples saw (the status warns of a bright or flickering one).
  RoomLightWatch roomLight_;
  DecodingWatch decodingCheck_;
};

}  // namespace slicecap::daemon
