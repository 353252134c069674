// What `slicecapd --check-hardware` found: one item per measurement, each with a verdict and
// what to do, and the configuration lines its measurements support.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "slicecap/core/tone_curve.hpp"

namespace slicecap::hwcheck {

enum class Verdict { Ok, Warn, Fail };

/// \brief "ok", "warn" or "fail".
const char* toString(Verdict verdict);

/// \brief One checked item: `finding` says what was measured (figures with units), `advice` what
/// to do about it (empty when nothing).
struct CheckItem {
  std::string name;  ///< e.g. "frame timing"
  Verdict verdict = Verdict::Ok;
  std::string finding;
  std::string advice;
};

/// \brief The figures measured, for the configuration and for tests; nullopt when not measured.
struct MeasuredFigures {
  std::optional<double> framePeriodUs, frameJitterUs;
  std::optional<int> framesDropped, framesSeen;
  std::optional<int> exposureLockDelayFrames;
  std::optional<double> lineTimeUs, readoutUs;
  /// The LED's light change after its recorded switch, on the frames' timestamps (the LED's own
  /// delay plus any error in the camera's timestamps).
  std::optional<double> ledOffsetUs;
  std::optional<double> ledOffsetSpreadUs;  ///< RMS residual of the line-time fit
  /// From the end of a frame's readout to its arrival at the application (ISP, hand-off).
  std::optional<double> deliveryLatencyUs;
  /// The recovered response: max relative difference of its ratios to white from linear and
  /// from sRGB over the codes the bracket covered.
  std::optional<double> curveFromLinear, curveFromSrgb;
  /// The frames' noise (capture::SensorNoise): read noise, fraction of full scale; shot noise as
  /// electrons at full scale, gain 1.
  std::optional<double> sensorReadNoise, sensorFullWellElectrons;
  /// The room light from LED-off frames: its flicker's frequency and depth ((max - min) / (max +
  /// min) of the light), and its level over the white references as a fraction of the LED's.
  std::optional<double> flickerHz, flickerDepth, roomToLed;
};

/// \brief The whole report.
struct HardwareReport {
  std::string cameraId;
  std::vector<std::string> cameras;  ///< the cameras and modes the backend lists
  std::vector<CheckItem> items;
  MeasuredFigures figures;
  /// `key = value` lines for slicecapd.conf (keys that config.cpp knows).
  std::vector<std::pair<std::string, std::string>> configLines;
  /// The recovered response curve, when the bracket could be fitted.
  std::optional<ToneCurve> responseCurve;
  std::optional<std::pair<double, double>> responseRange;  ///< the codes it covered

  /// \brief The worst verdict of the items (Ok when there are none).
  Verdict overall() const;
  /// \brief A human-readable report: cameras, one block per item, the configuration snippet.
  std::string text() const;
  nlohmann::json json() const;
  /// \brief The configuration snippet alone (what --write-config writes).
  std::string configSnippet() const;
};

}  // namespace slicecap::hwcheck
