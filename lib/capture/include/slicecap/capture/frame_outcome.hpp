// What the capture pipeline makes of one frame of a sweep: the seam between the per-frame
// pipeline (markers, pose, gate, sample) and its users, the daemon's frame loop and
// `slicecap process`.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/frame_sample.hpp"
#include "slicecap/capture/led_gate.hpp"
#include "slicecap/capture/light_model.hpp"
#include "slicecap/capture/marker_detector.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/capture/reject_reason.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/vision/pose.hpp"

namespace slicecap::capture {

/// \brief One frame's outcome. Exactly one of: a sample (an accepted LED-on frame), an ambient
/// frame (an LED-off frame kept to subtract room light from its neighbours; not a sample), or a
/// rejection with its reason (reject_reason.hpp).
struct FrameOutcome {
  enum class Kind { Sample, Ambient, Rejected };
  Kind kind = Kind::Rejected;
  std::optional<FrameSample> sample;  ///< set exactly when kind == Sample
  RejectReason rejectReason{};        ///< meaningful exactly when kind == Rejected
  std::string detail;                 ///< free text for logs and reports (e.g. "3 of 16 tags")
  /// \brief View elevation minus the slice's nominal, deg, whenever a pose was found (shown live
  /// so the person can correct the arm).
  std::optional<double> viewElevationErrorDeg;
  /// \brief What the pipeline measured, as far as it got (reports and tests).
  struct Measurement {
    int markerCount = 0;
    /// \brief The scale of the tracked search whose markers were used (from the latest pose, in
    /// the sheet's area); none when the whole frame was searched (no pose yet, or tracking missed).
    std::optional<DetectionScale> trackedScale;
    int detectionPasses = 0;       ///< detector calls on this frame (MarkerSearchResult)
    double detectionWorkPx = 0.0;  ///< their detectionWorkPx, at most the frame budget
    std::optional<Direction> view;  ///< toward the camera from the window centre
    double cameraDistanceMm = 0.0;
    double poseResidualPx = 0.0;
    std::optional<Direction> nominalLight;   ///< the slice's theta_i, phi_i from phi_v
    std::optional<Direction> measuredLight;  ///< from the point-light fit
    double measuredLightSigmaDeg = 0.0;
    double sharpness = 0.0;
    /// \brief The refined camera pose (camera-from-target), whenever one was found: texture
    /// capture (lib/btf) rectifies the window with it.
    std::optional<vision::Pose> pose;
    /// \brief The point-light fit to the white references, whenever it converged: its
    /// irradiance model normalises every texel of a texture capture.
    std::optional<PointLight> fittedLight;
    /// \brief The rows of the window and the white references, whenever a pose was found: the
    /// daemon's strobe switches the LED while no frame exposes them.
    std::optional<RowSpan> rowsOfInterest;
    /// \brief The white references' disagreement (the point-light fit's noise-weighted relative
    /// RMS residual) and the most the gate allows for this frame (noise plus the margin),
    /// whenever the fit converged.
    std::optional<double> referenceDisagreement;
    std::optional<double> referenceDisagreementLimit;
    /// \brief The room-light term over the white references as a fraction of their LED light
    /// (the LED-on reading less the term), whenever the references were read with one.
    std::optional<double> roomToLed;
    /// \brief Where a sample's room light came from, whenever it was read from two LED-off
    /// frames: their camera centres apart (mm, both located), the LED-on frame's camera centre
    /// from the nearer one's (mm, all three located), and the frames between the two
    /// (FrameMetadata::sequence apart; 2 when none was dropped with the LED alternating).
    std::optional<double> roomLightApartMm;
    std::optional<double> roomLightNearestMm;
    std::optional<std::int64_t> roomLightSequenceApart;
    /// \brief An LED-off frame right after another (the next sequence number), both located:
    /// their room light over the white references apart, as a fraction of it (the sum over the
    /// references and channels of |difference| over the mean). A flicker the frame duration does
    /// not hide shows here (the two frames saw it at phases a frame period apart); a steady one,
    /// or one the frame duration hides, leaves noise.
    std::optional<double> roomChange;
    /// \brief The black patch as the frame's decoding reads it against the white references: its
    /// LED light over the fitted light's irradiance there, times pi, over its albedo, averaged
    /// over the channels (1 when the decoding is right), whenever a sample was taken and the
    /// patch is in view. Under one tone curve it stays put from frame to frame; a curve stretched
    /// per frame (adaptive contrast) moves it (the daemon's decoding watch).
    std::optional<double> blackReading;
    /// \brief An 8-bit sample frame's window: per channel, the fraction of its pixels at code 0.
    /// About half at most where the light is at black and noise spreads it; nearly all when the
    /// camera's processing took the light below black (a colour matrix mixing the channels).
    std::optional<Rgb> windowAtBlack;
    /// \brief A sample's window light from the LED per channel (the window less the room light,
    /// over the fitted light's irradiance): the sample's value before it is held at 0. The LED
    /// only adds light, so a channel at or below 0 in most of a sweep's samples is a decoding
    /// that lost it (a colour matrix taking it below black; the daemon's decoding watch).
    std::optional<Rgb> windowLight;
  };
  Measurement measurement;
};

/// \brief Turns the frames of a sweep of `slice` into outcomes, in capture order. Implementations
/// keep state across frames (tracking, the last LED-off frame) and are reset between sweeps by
/// constructing a new one.
using FrameProcessor = std::function<FrameOutcome(const hal::Frame& frame, const SliceId& slice)>;

/// \brief A frame's outcome as the live loop gets it, with the metadata of the frame it is of:
/// possibly a frame or two after that frame came (an LED-on frame waits for the LED-off frame
/// after it, for its two-sided room-light term).
struct SettledFrame {
  hal::FrameMetadata metadata;
  FrameOutcome outcome;
};

/// \brief The daemon's frame loop's seam: each call hands over the sweep's next frame and returns
/// the outcomes it settled, in capture order (none, its own, or held frames' and its own).
/// `frame` nullptr: the sweep's stream has ended; every frame still held is settled as it can be
/// (an LED-on frame with the LED-off frame before it alone). Reset between sweeps by
/// constructing a new one.
using LiveFrameProcessor =
    std::function<std::vector<SettledFrame>(const hal::Frame* frame, const SliceId& slice)>;

/// \brief A LiveFrameProcessor that settles every frame at once through `processor` (a
/// processor that needs no later frame: tests' stand-ins, a room without LED-off frames).
inline LiveFrameProcessor settledAtOnce(FrameProcessor processor) {
  return [processor = std::move(processor)](const hal::Frame* frame, const SliceId& slice) {
    std::vector<SettledFrame> settled;
    if (frame) settled.push_back({frame->metadata, processor(*frame, slice)});
    return settled;
  };
}

}  // namespace slicecap::capture
