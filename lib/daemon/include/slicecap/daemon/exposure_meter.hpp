// Metering at sweep start: when the configuration leaves exposure to the camera, the daemon
// brings the brightest pixels to a level below clipping with the LED on, then keeps that exposure
// fixed for the sweep, so LED-on and LED-off frames are exposed alike.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/frame.hpp"

namespace slicecap::daemon {

/// \brief Options of the metering. The level and the headroom are a first choice, not measured on
/// a rig: the white reference patches are the brightest diffuse things in view, and a glossy
/// material's highlight, which passes by mid-sweep, needs room above them.
struct ExposureMeterParams {
  double startExposureUs = 10'000.0;
  /// The brightest `brightFraction` of the pixels (largest channel, linear) are brought to this
  /// fraction of full scale: about 1.5 stops of headroom below clipping.
  double targetLevel = 0.35;
  double brightFraction = 0.005;
  /// Done when the level is within this factor of the target (either way).
  double tolerance = 1.25;
  /// Frames skipped after each change: a camera applies new controls a few frames late.
  int settleFrames = 4;
  /// A frame taken before the change reached the camera (FrameMetadata::exposureLocks) or whose
  /// reported exposure is not the accepted one (libcamera reports each frame's own, which reaches
  /// the new value a few frames after the request that carried it) is skipped too; after this
  /// many frames since the change the metering ends where it is, off the target.
  int maxFramesPerChange = 30;
  /// Changes of exposure at most; then the last one stays.
  int maxSteps = 8;
  /// The longest exposure the metering sets: one frame at 30 fps. Longer would lower the frame
  /// rate and blur a moving rig; a scene too dark for it needs more gain (`gain`).
  double maxExposureUs = 33'333.0;
};

/// \brief The linear level (1 = full scale) at or above which `brightFraction` of the frame's
/// pixels lie, by their largest channel. 0 for an empty image.
double brightLevel(const hal::Frame& frame, double brightFraction);

/// \brief The metering as a sequence of steps the daemon carries out. Feed it every frame taken
/// since the camera accepted the last setting (`accepted`); it says to wait, to lock a new
/// setting, or that the setting it was given last is final.
class ExposureMeter {
 public:
  explicit ExposureMeter(ExposureMeterParams params = {});

  /// \brief The first setting to lock: the start exposure at the configured gain (nullopt: the
  /// camera's default).
  hal::ExposureSetting firstSetting(std::optional<double> gain) const;
  /// \brief What the camera set for the last request (clamped to its range). Call it for every
  /// lock the camera made since it started, and for nothing else: frames are matched to the
  /// setting by FrameMetadata::exposureLocks.
  void accepted(const hal::ExposureSetting& setting);
  /// \brief The camera refused the last request (Camera::lockExposure gave no lock, keeping the
  /// setting accepted before): the metering ends at that setting, off the target, saying why.
  void refused(const std::string& reason);

  struct Step {
    enum class Kind { Wait, Lock, Done };
    Kind kind = Kind::Wait;
    hal::ExposureSetting setting;  ///< Lock: the next setting; Done: the final one
  };
  /// \brief One frame taken at the accepted setting.
  Step onFrame(const hal::Frame& frame);

  /// \brief The last measured level, and whether it ended within the tolerance of the target
  /// (false: the camera's exposure range or resolution, the exposure limit, the step limit, a
  /// camera that did not apply or refused a change stopped the metering first; summary() says
  /// which).
  double lastLevel() const { return lastLevel_; }
  bool onTarget() const { return onTarget_; }
  int steps() const { return steps_; }
  /// \brief One line for the log and the status, e.g. "exposure locked at 8000 us, gain 2 ...".
  std::string summary() const;

 private:
  ExposureMeterParams params_;
  hal::ExposureSetting current_;
  int framesSinceChange_ = 0;
  std::uint32_t locksAccepted_ = 0;  ///< accepted() calls: the camera's locks since it started
  int steps_ = 0;
  double lastLevel_ = 0.0;
  bool onTarget_ = false;
  bool done_ = false;
  bool measured_ = false;
  std::string offTargetReason_;
};

}  // namespace slicecap::daemon
