// A sweep's decoding: the bracket's steps, its fit, and the stated fallbacks.
#include "slicecap/daemon/sweep_decoding.hpp"

#include <cstdio>
#include <algorithm>
#include <stdexcept>

#include "slicecap/io/target_json.hpp"
#include "slicecap/daemon/config.hpp"
#include "slicecap/daemon/slicecapd_error.hpp"

namespace slicecap::daemon {
namespace {

// A lock not seen in this many frames was not applied (a camera applies controls a few frames
// late: picamera2 issues 1278, 1333 put it at the buffer count + 3).
constexpr int kMaxFramesPerLock = 30;

}  // namespace

std::string toString(DecodingMode mode) {
  switch (mode) {
    case DecodingMode::Auto:
      return "auto";
    case DecodingMode::MeasuredCurve:
      return "measured-curve";
    case DecodingMode::Srgb:
      return "srgb";
  }
  return "auto";
}

DecodingMode decodingModeFromString(const std::string& value) {
  if (value == "auto") return DecodingMode::Auto;
  if (value == "measured-curve") return DecodingMode::MeasuredCurve;
  if (value == "srgb") return DecodingMode::Srgb;
  throw ConfigError("'" + value + "' is not auto, measured-curve or srgb");
}

nlohmann::json toJson(const SweepDecoding& d, const std::string& cameraId) {
  nlohmann::json json = {{"camera", cameraId},
                         {"decoding", io::toString(d.decoding.kind)},
                         {"note", d.note},
                         {"bracket_frames", d.bracketFrames.size()}};
  if (!d.warning.empty()) json["warning"] = d.warning;
  if (d.decoding.curve) {
    nlohmann::json points = nlohmann::json::array();
    for (const auto& [linear, encoded] : d.decoding.curve->points()) points.push_back({linear, encoded});
    json["curve"] = {{"name", d.decoding.curve->name()}, {"points", points}};
  }
  return json;
}

void recordDecodingCheck(const std::filesystem::path& file, const control::DecodingCheckView& figures,
                         const std::vector<std::string>& warnings) {
  nlohmann::json record = io::readJsonFile(file);
  nlohmann::json check = nlohmann::json::object();
  if (figures.blackReading) check["black_reading"] = *figures.blackReading;
  if (figures.blackReadingStep) check["black_reading_step"] = *figures.blackReadingStep;
  if (figures.blackReadingStepSigmas)
    check["black_reading_step_sigmas"] = *figures.blackReadingStepSigmas;
  if (figures.windowAtBlackChannel) check["window_at_black_channel"] = *figures.windowAtBlackChannel;
  if (figures.windowAtBlack) check["window_at_black"] = *figures.windowAtBlack;
  if (figures.windowUnlitChannel) check["window_unlit_channel"] = *figures.windowUnlitChannel;
  if (figures.windowUnlit) check["window_unlit"] = *figures.windowUnlit;
  if (figures.windowUnlitAtZero) check["window_unlit_at_zero"] = *figures.windowUnlitAtZero;
  if (figures.windowUnlitSigmas) check["window_unlit_sigmas"] = *figures.windowUnlitSigmas;
  if (figures.windowUnlitMeanSigmas)
    check["window_unlit_mean_sigmas"] = *figures.windowUnlitMeanSigmas;
  if (figures.windowStepChannel) check["window_step_channel"] = *figures.windowStepChannel;
  if (figures.windowStep) check["window_step"] = *figures.windowStep;
  if (figures.windowStepSigmas) check["window_step_sigmas"] = *figures.windowStepSigmas;
  check["warnings"] = warnings;
  record["check"] = std::move(check);
  io::writeJsonFileAtomically(file, record);
}

std::vector<std::string> recordedDecodingWarnings(const std::filesystem::path& session) {
  std::vector<std::filesystem::path> files;
  std::error_code error;
  for (std::filesystem::directory_iterator it(session / kDecodingFolder, error), end;
       !error && it != end; it.increment(error))
    if (it->path().extension() == ".json") files.push_back(it->path());
  std::sort(files.begin(), files.end());
  std::vector<std::string> out;
  for (const std::filesystem::path& file : files) {
    try {
      const nlohmann::json record = io::readJsonFile(file);
      if (!record.contains("check") || !record["check"].contains("warnings")) continue;
      for (const nlohmann::json& warning : record["check"]["warnings"])
        out.push_back("sweep " + file.stem().string() + ": " + warning.get<std::string>());
    } catch (const std::exception& e) {
      out.push_back("the decoding record " + file.string() + " could not be read: " + e.what());
    }
  }
  return out;
}

ResponseBracket::ResponseBracket(const hal::ExposureSetting& metered, std::uint32_t locks,
                                 capture::BracketPlan plan, double maxExposureUs, double maxGain)
    : settings_(plan.settings(metered, maxExposureUs, maxGain)), locks_(locks) {
  std::string why;
  if (!plan.isValid(&why)) throw SlicecapdError("bracket plan: " + why);
  settings_.push_back(metered);
}

void ResponseBracket::accepted() {
  ++locks_;
  framesSinceLock_ = 0;
}

void ResponseBracket::refused(const std::string& reason) {
  done_ = true;
  failure_ = "the camera refused bracket exposure " + std::to_string(current_ + 1) + " (" + reason + ")";
}

ResponseBracket::Step ResponseBracket::onFrame(const hal::Frame& frame) {
  if (done_) return {Step::Kind::Done, settings_.back()};
  ++framesSinceLock_;
  const bool restoring = current_ + 1 == settings_.size();
  if (frame.metadata.exposureLocks < locks_) {
    if (framesSinceLock_ < kMaxFramesPerLock) return {Step::Kind::Wait, {}};
    done_ = true;
    // The sweep goes on at whatever the camera has; its frames say their own exposure.
    if (!restoring)
      failure_ = "the camera's frames did not show bracket exposure " + std::to_string(current_ + 1) +
                 " within " + std::to_string(kMaxFramesPerLock) + " frames of its lock";
    return {Step::Kind::Done, settings_.back()};
  }
  if (restoring) {
    done_ = true;
    return {Step::Kind::Done, settings_.back()};
  }
  frames_.push_back(frame);
  ++current_;
  return {Step::Kind::Lock, settings_[current_]};
}

SweepDecoding decodingWithoutBracket(PixelEncoding encoding, DecodingMode mode,
                                     const std::string& cameraId, const std::string& why) {
  SweepDecoding out;
  if (encoding == PixelEncoding::Linear16) {
    out.decoding.kind = io::RecordedDecoding::Kind::Linear;
    out.note = "camera " + cameraId + " delivers linear 16-bit frames: no bracket needed";
    return out;
  }
  out.decoding.kind = io::RecordedDecoding::Kind::Srgb;
  if (mode == DecodingMode::Srgb) {
    out.note = "decoding = srgb: 8-bit frames read through the sRGB curve, no bracket taken";
    return out;
  }
  out.note = "8-bit frames read through the sRGB curve (fallback)";
  out.warning = "camera " + cameraId + ": " + why +
                "; this sweep decodes its 8-bit frames as sRGB, which a Pi's ISP or a UVC camera "
                "does not encode (ratios of unlike levels are off by up to ~25 %)";
  return out;
}

SweepDecoding decodingFromBracket(std::vector<hal::Frame> bracket, const std::string& bracketFailure,
                                  const BracketSubject& subject, const std::string& cameraId) {
  SweepDecoding out;
  const std::string advice =
      "; this sweep decodes its 8-bit frames as sRGB (the fallback). Keep the whole target in "
      "view and still, lit by the LED, while the sweep starts; if its whites clip, set a lower "
      "gain; a camera that cannot lock or report its exposure cannot be bracketed (decoding = "
      "srgb silences this)";
  if (!bracketFailure.empty()) {
    out = decodingWithoutBracket(PixelEncoding::Srgb8, DecodingMode::Auto, cameraId,
                                 "no response bracket: " + bracketFailure);
    out.warning = "camera " + cameraId + ": no response bracket: " + bracketFailure + advice;
    out.bracketFrames = std::move(bracket);
    return out;
  }
  capture::ResponseFitParams params;
  params.cameraName = cameraId;
  try {
    const capture::ResponseFit fit = capture::fitResponse(bracket, subject.target, subject.camera, params);
    out.decoding.kind = io::RecordedDecoding::Kind::MeasuredCurve;
    out.decoding.curve = fit.curve;
    out.note = "measured curve: " + fit.summary();
  } catch (const capture::ResponseCurveMisfit& misfit) {
    // Refused for its residual: the same fallback as a bracket that could not be fitted, said
    // with the figure and what to change, not the advice about the target's view.
    char figure[96];
    std::snprintf(figure, sizeof figure, "RMS residual %.1f %% > %.1f %%",
                  100.0 * misfit.rmsLogResidual(), 100.0 * misfit.limit());
    out.decoding.kind = io::RecordedDecoding::Kind::Srgb;
    out.note = std::string("8-bit frames read through the sRGB curve (fallback: the measured "
                           "curve was refused, ") + figure + ")";
    out.warning = std::string("the measured response curve was refused: ") + misfit.what() +
                  "; this sweep decodes its 8-bit frames as sRGB (the fallback), which this "
                  "camera does not encode either (ratios of unlike levels are off by up to ~25 %)";
  } catch (const capture::ResponseFitError& error) {
    out.decoding.kind = io::RecordedDecoding::Kind::Srgb;
    out.note = "8-bit frames read through the sRGB curve (fallback: the bracket could not be fitted)";
    out.warning = std::string("the response bracket could not be fitted: ") + error.what() + advice;
  }
  out.bracketFrames = std::move(bracket);
  return out;
}

}  // namespace slicecap::daemon
