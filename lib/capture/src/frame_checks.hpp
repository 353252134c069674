// The frame pipeline's checks of one frame that need no pipeline state: can it be read, how sharp
// are its marker edges, what noise alone lets the white references disagree by.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/capture/led_gate.hpp"
#include "slicecap/capture/light_model.hpp"
#include "slicecap/capture/linear_view.hpp"
#include "slicecap/capture/marker_detector.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture::frame_checks {

/// \brief True when the camera reported the frame's exposure and gain (else areas are read
/// unscaled).
bool exposureKnown(const hal::Frame& frame);

/// \brief A reason and detail for a rejection by the window and white-reference gate.
struct GateFailure {
  RejectReason reason;
  std::string detail;
};

/// \brief The relative disagreement of the white references that noise alone exceeds with the
/// probability of a one-sided standard normal beyond `sigmas`: the fit's noise RMS times the
/// chi-square quantile over its degrees of freedom (Wilson-Hilferty), square-rooted.
double noiseAllowance(const LightFit& fit, double sigmas);

/// \brief Motion smears the edges across the motion, so the blurriest quarter of the markers'
/// edges counts: that quarter's sharpness (0 when no edge could be measured).
double blurSharpness(const LinearView& view, const std::vector<const DetectedMarker*>& markers);

/// \brief "the LED switched while rows A..B were exposed".
std::string ledTransitionDetail(const RowSpan& rows);

/// \brief Why `frame` cannot be read as this camera's frame ("bad_frame"), or nullopt when it can.
std::optional<std::string> badFrameDetail(const hal::Frame& frame,
                                          const vision::CameraIntrinsics& k);

/// \brief `outcome` as a rejection for `reason`.
FrameOutcome rejected(RejectReason reason, std::string detail, FrameOutcome outcome = {});

}  // namespace slicecap::capture::frame_checks
