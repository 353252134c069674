// The daemon's first collaborator: what captures a slice's sweep (its camera, its frame pipeline,
// and what a response bracket is fitted against). lib/rig builds it from slicecapd.conf; tests
// give fakes.
#pragma once

#include <memory>
#include <optional>

#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/core/tone_curve.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"
#include "slicecap/hal/camera.hpp"

namespace slicecap::daemon {

/// \brief The camera and pipeline of each slice's sweep. Called on the daemon's event loop.
class CaptureRig {
 public:
  virtual ~CaptureRig() = default;

  /// \brief The camera for a sweep of `slice`: a live camera returns the one it opened at start
  /// (so a missing camera fails the start, before READY); the file camera opens that slice's
  /// recording. Throws (a std::exception naming the device or file) when it cannot; the sweep
  /// then pauses with the message.
  virtual std::shared_ptr<hal::Camera> camera(const SliceId& slice) = 0;

  /// \brief A fresh per-frame pipeline for a sweep run of `slice` (it keeps tracking state across
  /// frames), decoding 8-bit frames through `toneCurve` (nullopt: sRGB). It calls `observer`
  /// (when set: texture capture) for every frame it processes. Its outcomes may settle frames
  /// late (capture::makeLiveFramePipeline: an LED-on frame waits for the LED-off frame after
  /// it); capture::settledAtOnce wraps a processor that needs no wait.
  virtual capture::LiveFrameProcessor pipeline(const SliceId& slice, capture::FrameObserver observer,
                                               const std::optional<ToneCurve>& toneCurve) = 0;

  /// \brief The target and camera model a response bracket of `slice` is fitted against; nullopt
  /// when this rig cannot fit one (the sweep then decodes as sRGB and its status says so).
  virtual std::optional<BracketSubject> bracketSubject(const SliceId& slice) = 0;
};

}  // namespace slicecap::daemon
