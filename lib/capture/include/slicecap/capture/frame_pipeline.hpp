// The per-frame capture pipeline: markers, pose, light direction, gate, BRDF sample.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "slicecap/capture/area_reading.hpp"
#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/capture/marker_detector.hpp"
#include "slicecap/core/tone_curve.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::capture {

/// \brief The gate's tolerances and the pipeline's options.
struct PipelineSettings {
  MarkerDetectorSettings detector;
  int minMarkers = 4;                  ///< fewer detected markers: "too_few_markers"
  double elevationToleranceDeg = 5.0;  ///< |theta_v - nominal| above this: "elevation_off"
  double maxPoseResidualPx = 1.5;      ///< RMS reprojection error above this: "pose_residual"
  /// \brief Edge sharpness of the markers' borders (largest 1-px step over the edge's full step,
  /// ~1 when sharp, ~1/L for L px of motion blur) below this: "blurred".
  double minSharpness = 0.4;
  /// \brief Any window or white-reference pixel channel at or above this fraction of full scale:
  /// "window_clipped".
  double clipFraction = 0.98;
  /// \brief The margin for real occlusion: the point-light fit's relative RMS residual over the
  /// white references (each weighted by its expected noise) above this plus what noise explains
  /// means something (the light arm, a finger) covers part of them: "window_occluded". It also
  /// holds what the point-light model misses (paper not quite Lambertian, vignetting).
  double maxReferenceResidual = 0.05;
  /// \brief What noise explains: the residual that noise alone exceeds with the one-sided
  /// normal probability beyond this many sigmas (3.09: one unoccluded frame in 1000 rejected),
  /// from the chi-square distribution of the weighted residuals (docs/capture-gates.md).
  double referenceNoiseSigmas = 3.09;
  /// \brief The sensor's noise, from which each reading's expected noise follows.
  SensorNoise noise{};
  /// \brief Pixels of a white reference closer than this to its outline are not read: the
  /// blur the gate lets through (1 / minSharpness = 2.5 px) plus half a pixel of pose error.
  double referenceInsetPx = 3.0;
  /// \brief Side of the square of the window whose pixels are averaged, as a fraction of the
  /// window.
  double windowSampleFraction = 0.2;
  /// \brief Each accepted frame's whole window is also read as this many cells per side, each a
  /// sample at its own light and view directions (FrameSample::cells; 0: none). 8 on the default
  /// target (40 mm window, 33-38 mm read): cells 4-5 mm apart, 0.8-0.9 deg of view and of light
  /// direction at 300 mm; at 75/75 the half vector tilts ~3 deg from cell to cell, ~0.8 deg of
  /// the slice parameter (3.7 deg of tilt per degree), about the 0.6-0.75 deg width of a sharp
  /// metal's peak. At 75 deg, where the window is foreshortened to ~34 px, a cell is still
  /// ~3.5 px deep, more than the 2.5 px of blur the gate lets through. 16-20 x 3.5-16 px a cell:
  /// ~60-250 px averaged, noise well below the point-light model's 5 % margin.
  int windowCellsPerSide = 8;
  /// \brief The cells' grid leaves out the window's pixels this close to its outline, at the
  /// frame's pose (as referenceInsetPx does for the references).
  double windowCellInsetPx = 3.0;
  /// \brief The measured light direction replaces the nominal one when its sigma is below this.
  double measuredLightMaxSigmaDeg = 0.5;
  double nominalLightDistanceMm = 300.0;  ///< start of the point-light fit
  /// \brief LED-on frames need an LED-off frame to subtract (false: no room light is subtracted,
  /// not even an LED-off frame's that came: slicecapd's led_alternate = false, a dark room). An
  /// LED-off frame whose exposure the camera did not report (0) is subtracted only from LED-on
  /// frames without one either, and the other way round: else "no_ambient_frame".
  bool requireAmbient = true;
  /// \brief Locate each LED-off frame's own pose (one more detection per LED pair) and sample its
  /// room light at the same target points as the LED-on frame's, not at the same pixels: the
  /// camera moves between the two. Off in the live loop (the CPU budget), on offline
  /// (processRecording).
  bool poseAmbientFrames = false;
  /// \brief "room_light_unseen": an LED-on frame whose two LED-off frames saw the window's room
  /// light differ by more than referenceNoiseSigmas of their noise in a channel and by more than
  /// maxRoomLightChange of the window's LED light (RGB vectors: it changes along the camera's
  /// path there), while the nearer of them was taken more than this far from it (camera
  /// centres, mm; all three located): the room light at its own place was seen by neither, and no weighting recovers it (a glint passed between them; the frames between
  /// were dropped). 15 mm: a hand-held 8 s sweep at the 75 deg view elevation (a 290 mm circle)
  /// moves the camera about 9 mm a 40 ms frame period, so an LED-on frame with its LED-off
  /// neighbours delivered is kept (15 is the value to use). 0: off, the default: a rejected frame
  /// is a bin the reconstruction interpolates, and on the simulated session (every frame 20-40 mm
  /// from the next, 3 % room light) the gate cost the table more than the samples it removed
  /// were wrong (`capture-offline` dE 6.51 -> 7.11, slicecapd 7.52 -> 8.08), while on the RAW
  /// room-light session (15 % room light, 60 % of frames dropped) it helped (dE -13 %, one run).
  /// slicecapd.conf room_light_unseen_mm, `--room-light-unseen-mm`. None: off, except that
  /// processRecording then takes the recording's own (io::Recording::roomLightUnseenMm), so a
  /// gated session is reproduced offline; 0 is off whatever the recording says.
  std::optional<double> maxRoomLightDistanceMm{};
  /// \brief See maxRoomLightDistanceMm. 5 %: on simulated sweeps (`slicecap simulate`, every
  /// frame 20-40 mm from the next) the far LED-on frames whose room light changed by less read
  /// a median error of 0.3-1.1 %, those above 2.3-2.9 % (docs/real-sensors.md).
  double maxRoomLightChange = 0.05;
  /// \brief processRecording's ambient term: false reproduces the live loop exactly (the LED-off
  /// frame before, at the LED-on frame's pixels), e.g. to compare a daemon's session with it.
  bool offlineTwoSidedAmbient = true;
  /// \brief How 8-bit frames are decoded to linear light: through this curve (e.g. the
  /// camera's response measured at sweep start, fitResponse in response_curve.hpp); nullopt:
  /// as sRGB. 16-bit frames are linear either way. processRecording uses the recording's own
  /// decoding when this is nullopt.
  std::optional<ToneCurve> toneCurve{};
  /// \brief An HDR sweep's frames (processRecording sets it for a recording with exposure
  /// levels): a clipped window is no rejection (the white references still are), and every
  /// sample carries its window cells and irradiance (FrameSample::hdr) for the per-bin merge.
  bool hdr = false;
};

/// \brief One LED-off frame's share of an LED-on frame's room-light term.
struct AmbientTerm {
  const hal::Frame* frame = nullptr;
  /// \brief The LED-off frame's own pose when it was located: the same target point is read
  /// there (else at the LED-on frame's pixel).
  std::optional<vision::Pose> pose;
  double weight = 1.0;  ///< the terms of one LED-on frame sum to 1
};

/// \brief An LED-off frame and the pose it was located at (FrameOutcome::Measurement::pose of its
/// Ambient outcome, offline).
struct LocatedAmbientFrame {
  hal::Frame frame;
  vision::Pose pose;
};

/// \brief A pose and the time of the frame it was located in (hal::FrameMetadata::timestampUs).
struct TimedPose {
  vision::Pose pose;
  std::int64_t timestampUs = 0;
};

/// \brief Turns the frames of one sweep into outcomes; keeps the latest LED-off frame. Construct
/// a new one per sweep.
class FramePipeline {
 public:
  /// \brief Throws CaptureError naming the problem for an invalid camera or target.
  FramePipeline(vision::TargetGeometry target, vision::CameraModel camera,
                PipelineSettings settings = {});
  ~FramePipeline();
  FramePipeline(FramePipeline&&) noexcept;
  FramePipeline& operator=(FramePipeline&&) noexcept;

  /// \brief One frame: an LED-off frame becomes Ambient (and is kept for the next LED-on frames);
  /// an LED-on frame a Sample or a Rejection with its reason. Never throws for bad pixels: a frame
  /// of the wrong size or encoding is rejected as "bad_frame".
  FrameOutcome process(const hal::Frame& frame, const SliceId& slice);
  /// \brief Offline use: the ambient frame for LED-on frames before the first LED-off one (the
  /// live loop just rejects those as "no_ambient_frame"). A frame process() would reject as
  /// "bad_frame" is ignored, here and by setFollowingAmbientFrame.
  void setAmbientFrame(const hal::Frame& frame);
  /// \brief Offline use: the LED-off frame that follows the coming LED-on frame(s). Their ambient
  /// term is then interpolated between the LED-off frames on both sides (ambientTermsFor; on a
  /// specular material the room light's reflection changes along the sweep: one side alone is
  /// biased by half a step). When that frame's turn comes, process() reuses it. The live loop
  /// does not call this and keeps the one-sided estimate, so every frame's outcome is known when
  /// it arrives.
  void setFollowingAmbientFrame(const hal::Frame& frame);
  /// \brief The room-light term the pipeline uses for an LED-on frame taken at `timeUs` and
  /// located at `pose` (FrameOutcome::Measurement::pose; none when it was not): the LED-off frame
  /// before it and, once setFollowingAmbientFrame gave one (offline), the one after, weighted
  /// linearly where the camera was between them (its centre projected between theirs) when all
  /// three are located and theirs are apart, else in time. Empty when there is no LED-off frame.
  /// The pointers stay valid until the next process() or set*AmbientFrame() call.
  std::vector<AmbientTerm> ambientTermsFor(
      std::int64_t timeUs, const std::optional<vision::Pose>& pose = std::nullopt) const;
  /// \brief Offline HDR: the located LED-off frames of another (longer) exposure level nearest the
  /// coming LED-on frames in time, in time order. An LED-on frame whose own room-light term has
  /// no LED-off frame, or one that was not located (a short exposure's markers sit a few codes
  /// above black), takes its room light from these instead, weighted as its own: every
  /// frame is read per unit of exposure x gain, so another level's LED-off frames measure the
  /// same room light, and read at their own poses they read the same target points, where the
  /// LED-on frame's pixels would read other points after the hand moved (docs/method.md 9.3).
  /// An empty list ends the stand-ins.
  void setStandInAmbientFrames(std::vector<LocatedAmbientFrame> frames);
  /// \brief The pose the marker search tracks from and when it was located; none while the
  /// target is lost (never located, or not for MarkerDetectorSettings::trackingPatienceFrames).
  std::optional<TimedPose> latestLocation() const;
  /// \brief HDR: the longest exposure level's latest location, handed to a shorter level's
  /// pipeline before each of its frames. The search tracks from it when it is newer than this
  /// pipeline's latest location, tracked or dropped (or this one has none); the re-acquisition
  /// passes go on where they were (MarkerSearch::trackFrom). A short level's frames are too dark
  /// to re-acquire a lost target in a frame's budget (its paper a few codes above black: the
  /// coarse passes miss it), and its own latest pose is a level block old; around a fresh pose
  /// the tracked pass, at the scale the markers' cells need, finds them (docs/method.md 9.3). The
  /// pose also predicts the rows the LED-state check reads, and while it is tracked the level's
  /// LED-off frames do not search for the target.
  void trackFrom(const TimedPose& location);

 private:
  bool offOverSampleRows(const hal::Frame& frame) const;
  struct State;
  struct Located;
  std::unique_ptr<State> state_;
};

/// \brief Sees a frame with its outcome and, for an LED-on frame, the room-light term the
/// pipeline used for it (FramePipeline::ambientTermsFor; empty for none or an LED-off frame):
/// texture capture (lib/btf) rectifies accepted frames with it. The term's frames stay valid only
/// during the call.
using FrameObserver = std::function<void(const hal::Frame& frame, const FrameOutcome& outcome,
                                         const std::vector<AmbientTerm>& ambient)>;

/// \brief A FramePipeline as the FrameProcessor the daemon's frame loop calls (one per exposure
/// level for frames that carry one, FrameMetadata::exposureLevel: an HDR sweep); `observer` (if
/// set) sees every frame after the pipeline, before the processor returns (the daemon's texture
/// capture). Whatever the observer throws passes through the processor.
FrameProcessor makeFramePipeline(const vision::TargetGeometry& target,
                                 const vision::CameraModel& camera,
                                 const PipelineSettings& settings = {},
                                 FrameObserver observer = {});

/// \brief The live loop's pipeline with the offline default's two-sided room-light term
/// (processRecording with offlineTwoSidedAmbient): each LED-on frame (FrameMetadata::ledOn) is
/// held until the next frame labelled LED-off of its exposure level arrives, then processed with
/// that frame as its following room light (FramePipeline::setFollowingAmbientFrame), then the
/// LED-off frame; the same calls, in the same order, as processRecording makes on the recorded
/// frames, so a recording of the sweep processed offline gives the same samples (with
/// settings.poseAmbientFrames, which offline sets, and a frame budget the target is found in).
/// A frame settles one LED block late (led_frames_per_state frames). At the stream's end (frame
/// nullptr) the held frames settle with the LED-off frame before them alone, as offline.
/// settings.requireAmbient false (no LED-off frames to wait for): every frame settles at once.
LiveFrameProcessor makeLiveFramePipeline(const vision::TargetGeometry& target,
                                         const vision::CameraModel& camera,
                                         const PipelineSettings& settings = {},
                                         FrameObserver observer = {});

}  // namespace slicecap::capture
