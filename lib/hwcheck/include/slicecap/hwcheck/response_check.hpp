// The camera's response curve from a bracket of the target's white and black references.
#pragma once

#include <optional>
#include <string>

#include "slicecap/capture/response_curve.hpp"
#include "slicecap/hwcheck/check_report.hpp"
#include "slicecap/hwcheck/check_rig.hpp"

namespace slicecap::hwcheck {

struct ResponseCheck {
  std::optional<capture::ResponseFit> fit;
  std::string error;  ///< why there is no fit (a ResponseFitError's message, or a lock refused)
  double meteredExposureUs = 0.0;
  std::optional<double> fromLinear, fromSrgb;  ///< curveDistance to those curves
};

/// \brief The largest relative difference between `a` and `b` in the ratio of a code's linear
/// value to that of `referenceCode` (each curve normalised there: a ratio of two regions is what
/// a capture uses, so a curve's scale does not matter), over codes lowCode..highCode.
double curveDistance(const ToneCurve& a, const ToneCurve& b, double lowCode, double highCode,
                     double referenceCode);

/// \brief Meters an exposure (the brightest 0.5 % of the frame's largest channel near code 160,
/// as the daemon's metering aims), locks each step of `plan` around it, keeps the first frame of
/// each lock and fits the response (capture::fitResponse) with the LED on. Fit failures are
/// values (`error`), not exceptions; throws what CheckRig throws.
ResponseCheck checkResponse(CheckRig& rig, const vision::TargetGeometry& target,
                            const vision::CameraModel& camera,
                            const capture::BracketPlan& plan = {});

CheckItem responseItem(const ResponseCheck& check, const std::string& cameraId);

}  // namespace slicecap::hwcheck
