// A processed camera's response (its ISP's tone curve) recovered from a bracket of the target's
// white and black references, so that 8-bit frames can be decoded to linear light (issue 27).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/capture/marker_detector.hpp"
#include "slicecap/core/error.hpp"
#include "slicecap/core/tone_curve.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::capture {

/// \brief Which exposures the bracket takes, relative to the metered one. The range must exceed
/// the white references' albedo over the black patch's (0.85 / 0.04 = 21 on the default target)
/// so that some black observation at the longest exposure is as bright as some white one at the
/// shortest: that overlap is what ties the dark end of the curve to the bright end. The default,
/// x1/32 .. x4 in whole stops, spans 128; the metering puts the brightest pixels at 0.35 of full
/// scale, so x4 clips the brightest channel of the whites and x1/32 leaves the black patch below
/// code 3 (both weighted out), while everything between is covered twice or more.
struct BracketPlan {
  /// Exposure x gain of each bracket frame over the metered one, ascending, > 0.
  std::vector<double> factors{1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0 / 2, 1.0, 2.0, 4.0};

  /// \brief False with a reason when there are fewer than ResponseFitParams::minExposures
  /// factors, or one is not positive or not above the one before.
  bool isValid(std::string* error = nullptr) const;
  /// \brief The settings to lock, one per factor: the exposure scaled, capped at maxExposureUs
  /// (a longer one lowers the frame rate), the rest of the factor put on the gain (capped at
  /// maxGain). The fit reads each frame's own reported exposure and gain, so a capped step is a
  /// repeated exposure, not an error. The gain stays metered.gain (nullopt: the camera's default)
  /// where the exposure is not capped; a capped step takes metered.gain (or 1) times the rest.
  std::vector<hal::ExposureSetting> settings(const hal::ExposureSetting& metered,
                                             double maxExposureUs = 33'333.0,
                                             double maxGain = 16.0) const;
};

/// \brief Options of the fit. Codes are 8-bit values.
struct ResponseFitParams {
  /// A patch area whose mean code is at or above this (or with more than 1 % of its pixels at
  /// 255) is clipped and left out.
  double clipCode = 250.0;
  /// ... at or below this (or more than 1 % at 0): too dark, its mean biased by the clamp at 0.
  double darkCode = 3.0;
  /// Each reference patch is cut into areas about this size (mm); each area has its own unknown
  /// irradiance (the LED's falloff over the target), and its mean code is one observation a frame.
  double areaMm = 6.0;
  /// Each area is inset by this fraction of its smaller side: a slightly wrong pose or blur must
  /// not mix in the window, a marker or the paper around the black patch.
  double insetFraction = 0.2;
  /// An area needs at least this many pixels.
  int minPixels = 16;
  /// Fewer distinct exposures (x gain) than this: "too few exposures".
  int minExposures = 4;
  /// Weight of the curvature penalty on ln(linear) over ln(code) (zero for a power law) against
  /// the observations' chi-square (their weights are 1 / standard error): it bridges codes no
  /// observation has and keeps the curve from following the ~1 % noise of single observations
  /// between knots. A real curve's own curvature costs a few units x this, far below the chi-square
  /// of ~1000 observations. docs/linear-light.md gives the figures at x0.1 and x10.
  double smoothness = 300.0;
  /// The largest RMS residual (in ln(linear), ResponseFit::rmsLogResidual) a curve may leave
  /// and be used. One curve fits every frame of a camera whose processing is fixed; a curve the
  /// ISP changes from frame to frame (adaptive contrast) leaves residuals no smooth curve
  /// removes, and decoding through it would be off by as much. The figures:
  /// docs/results/2026-12-06-response-gate.md.
  double maxRmsLogResidual = 0.04;
  MarkerDetectorSettings detector;
  int minMarkers = 4;
  double maxPoseResidualPx = 1.5;
  /// Named in error messages: the camera the bracket came from.
  std::string cameraName = "the camera";

  bool isValid(std::string* error = nullptr) const;
};

/// \brief One patch area's mean code in one frame of one channel.
struct ResponseObservation {
  int area = 0;           ///< index of the unknown irradiance (area x channel)
  double code = 0.0;      ///< mean 8-bit code over the area's pixels
  double exposure = 0.0;  ///< the frame's exposure (us) x gain
  double albedo = 1.0;    ///< the area's albedo in this channel
  double weight = 1.0;    ///< 1 / (standard error of ln(code)); 0 leaves it out
};

/// \brief The recovered response.
struct ResponseFit {
  /// Named "measured": encoded = code / 255 against linear, decode(1) = 1.
  ToneCurve curve = ToneCurve::linear();
  /// The codes the observations used in the fit covered; below, the curve is a straight line to
  /// (0, 0) (the linear toe of sRGB and of ISP tables); above, the slope of its last 8 codes
  /// carried on to 255, which is where linear 1 is put.
  double lowestCode = 0.0, highestCode = 0.0;
  int exposures = 0;        ///< distinct exposure x gain values in the bracket
  int observationsUsed = 0;  ///< area x channel x frame means inside the codes' range
  int observationsLeftOut = 0;  ///< clipped or too dark
  int framesWithOwnPose = 0;    ///< the rest used the pose of the nearest located frame
  /// RMS of the fit's residuals in ln(linear), over the used observations (about the relative
  /// error of one observation: noise and the model's shortfall).
  double rmsLogResidual = 0.0;
  /// \brief One line: codes covered, exposures, observations, residual.
  std::string summary() const;
};

/// \brief A bracket that cannot be fitted: the message names the camera (and the frames) and says
/// what to configure or change.
class ResponseFitError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief A fitted curve refused for its residual (above ResponseFitParams::maxRmsLogResidual):
/// the camera's processing does not follow one curve. The message names the camera, the figure,
/// the limit and the likely cause; the figures are kept for the status.
class ResponseCurveMisfit : public ResponseFitError {
 public:
  ResponseCurveMisfit(const std::string& message, double rmsLogResidual, double limit)
      : ResponseFitError(message), rmsLogResidual_(rmsLogResidual), limit_(limit) {}
  double rmsLogResidual() const { return rmsLogResidual_; }
  double limit() const { return limit_; }

 private:
  double rmsLogResidual_, limit_;
};

/// \brief Throws ResponseCurveMisfit naming `source` when `fit` leaves a larger RMS residual
/// than params.maxRmsLogResidual; fitResponse calls it on its final curve.
void checkResponseResidual(const ResponseFit& fit, const ResponseFitParams& params,
                           const std::string& source);

/// \brief Fits the response to observations (already measured): unknowns ln(linear) at every
/// code between the lowest and the highest observed and ln(irradiance) per area; each
/// observation says ln decode(code) - ln E_area = ln exposure (Debevec and Malik's least
/// squares, here on mean codes, with the curvature penalty in ln(code)). Throws
/// ResponseFitError when fewer than minExposures exposures remain, no observation is usable, or
/// the fit is not strictly increasing. `source` names the data in those messages.
ResponseFit fitResponseCurve(const std::vector<ResponseObservation>& observations,
                             const ResponseFitParams& params, const std::string& source);

/// \brief What measureBracket read off a bracket.
struct BracketObservations {
  std::vector<ResponseObservation> observations;
  /// Per observation, how many of its pixels had each code: fitResponse refits on the code whose
  /// decoded value is the mean of the pixels' decoded values (the pipeline averages linear
  /// values; a mean of codes is biased by the curve's bend where the noise is a large fraction
  /// of the signal, near black).
  std::vector<std::array<std::uint32_t, 256>> histograms;
  int framesWithOwnPose = 0;
  std::string source;  ///< the camera and the frames, for messages
};

/// \brief fitResponse's first half: the poses and every area's mean code per channel and frame.
/// Throws as fitResponse for what it checks (frames, exposures, the target).
BracketObservations measureBracket(const std::vector<hal::Frame>& bracket,
                                   const vision::TargetGeometry& target,
                                   const vision::CameraModel& camera,
                                   const ResponseFitParams& params = {});

/// \brief Recovers the response of the camera that took `bracket` (measureBracket, then
/// fitResponseCurve, refitted twice on the codes of the pixels' mean decoded values): 8-bit
/// frames of `target` with
/// the LED on, at several exposures (BracketPlan), the camera and target still (hand-held is fine
/// when each frame finds its own pose). Each frame's pose comes from its markers (the frame
/// pipeline's detector and planar pose); every white and black patch is cut into areas and each
/// area's mean code per channel is an observation with the frame's exposure x gain and the
/// patch's albedo. One curve for all channels (an ISP's gamma is the same on each; the colour
/// gains come before it and fall into the areas' irradiances). Throws ResponseFitError naming
/// params.cameraName and the frames: no frames or not 8-bit, target not found in any frame, too
/// few exposures, every area clipped or black, a fit that is not increasing; and
/// ResponseCurveMisfit (a ResponseFitError) when the final curve's residual is above
/// params.maxRmsLogResidual (checkResponseResidual).
ResponseFit fitResponse(const std::vector<hal::Frame>& bracket, const vision::TargetGeometry& target,
                        const vision::CameraModel& camera, const ResponseFitParams& params = {});

}  // namespace slicecap::capture
