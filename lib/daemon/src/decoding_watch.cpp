// The processed stream's decoding as the sweep's samples see it, and the status's warnings.
#include "slicecap/daemon/decoding_watch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "slicecap/core/median.hpp"

namespace slicecap::daemon {
namespace {

void keepLatest(std::deque<double>& values, double value) {
  values.push_back(value);
  while (values.size() > DecodingWatch::kSamples) values.pop_front();
}

std::optional<double> median(const std::deque<double>& values) {
  if (values.empty()) return std::nullopt;
  std::vector<double> sorted(values.begin(), values.end());
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  return sorted[sorted.size() / 2];
}

// The mean of `values` and that mean in its standard errors (none for fewer than 2).
std::optional<std::pair<double, double>> meanAndSigmas(const std::deque<double>& values) {
  if (values.size() < 2) return std::nullopt;
  double sum = 0.0, sumSquares = 0.0;
  for (double v : values) sum += v, sumSquares += v * v;
  const double n = double(values.size()), mean = sum / n;
  const double variance = std::max(0.0, (sumSquares - n * mean * mean) / (n - 1.0));
  const double standardError = std::sqrt(variance / n);
  return std::pair{mean, standardError > 0.0 ? std::abs(mean) / standardError : 0.0};
}

// A channel's LED light over the latest samples as the refusal judges it.
struct UnlitFigures {
  double atOrBelowZero = 0.0;  // fraction
  double atZero = 0.0;         // fraction exactly 0
  double medianSigmas = 0.0;   // the median in its robust standard errors
  std::optional<double> trimmedMeanSigmas;  // from kMinSamples samples on
};

UnlitFigures unlitFigures(const std::deque<double>& lights) {
  UnlitFigures out;
  const double n = double(lights.size());
  for (double v : lights) {
    out.atOrBelowZero += v <= 0.0 ? 1.0 / n : 0.0;
    out.atZero += v == 0.0 ? 1.0 / n : 0.0;
  }
  const double median = slicecap::median({lights.begin(), lights.end()});
  std::vector<double> deviations;
  for (double v : lights) deviations.push_back(std::abs(v - median));
  // The noise from the median absolute deviation (a Gaussian's sigma is 1.4826 MAD): robust to
  // a highlight's samples. The median's standard error is 1.2533 sigma / sqrt(n).
  const double sigma = 1.4826 * slicecap::median(std::move(deviations));
  const double standardError = 1.2533 * sigma / std::sqrt(n);
  const double cap = DecodingWatch::kSigmasCap;
  const auto ratio = [cap](double value, double error) {
    return error > 0.0 ? std::clamp(value / error, -cap, cap)
           : value < 0.0 ? -cap
           : value > 0.0 ? cap
                         : 0.0;
  };
  out.medianSigmas = ratio(median, standardError);
  // The mean of the samples within kTrimSigmas of the median (a highlight's are not the
  // channel's dark level), against its own standard error: more sensitive than the median where
  // the noise is wide, and steady enough from kMinSamples samples on.
  double sum = 0.0, squares = 0.0, kept = 0.0;
  for (double v : lights)
    if (sigma == 0.0 || std::abs(v - median) <= DecodingWatch::kTrimSigmas * sigma)
      sum += v, squares += v * v, kept += 1.0;
  if (lights.size() >= DecodingWatch::kMinSamples && kept >= 2.0) {
    const double mean = sum / kept;
    const double variance = std::max(0.0, (squares - kept * mean * mean) / (kept - 1.0));
    out.trimmedMeanSigmas = ratio(mean, std::sqrt(variance / kept));
  }
  return out;
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %%", 100.0 * fraction);
  return text;
}

constexpr const char* kChannelNames[3] = {"R", "G", "B"};

}  // namespace

void DecodingWatch::reset() {
  readings_.clear();
  steps_.clear();
  for (auto& channel : atBlack_) channel.clear();
  for (auto& channel : lights_) channel.clear();
  for (auto& channel : windowSteps_) channel.clear();
  lastWindowLight_.reset();
  lastWindowSequence_.reset();
  lastSequence_.reset();
  eightBit_ = false;
}

void DecodingWatch::note(const capture::FrameOutcome& outcome, std::uint64_t sequence) {
  if (outcome.kind != capture::FrameOutcome::Kind::Sample) return;
  const capture::FrameOutcome::Measurement& m = outcome.measurement;
  if (m.blackReading && std::isfinite(*m.blackReading)) {
    // Samples of consecutive frames only (an LED block's, a frame period apart): the pose, the
    // light and the exposure barely move between them, a curve stretched from the frame before
    // (an LED-off frame's for the first, an LED-on frame's for the next) does. Farther apart,
    // the hand's motion moves the reading through the curve's own small errors.
    if (!readings_.empty() && lastSequence_ && sequence == *lastSequence_ + 1 &&
        std::abs(readings_.back()) > 0.0)
      keepLatest(steps_, *m.blackReading / readings_.back() - 1.0);
    keepLatest(readings_, *m.blackReading);
    lastSequence_ = sequence;
  }
  if (m.windowAtBlack) {
    eightBit_ = true;
    for (int c = 0; c < 3; ++c) keepLatest(atBlack_[c], (*m.windowAtBlack)[c]);
  }
  // An HDR sweep's shorter levels leave a dark channel in the noise of black by design (they are
  // exposed for the highlight): only the longest level, metered on the target, says whether the
  // decoding lost a channel the LED lights.
  const bool shortLevel = outcome.sample && outcome.sample->hdr && outcome.sample->hdr->exposureLevel > 0;
  if (m.windowLight) {
    if (!shortLevel)
      for (int c = 0; c < 3; ++c) keepLatest(lights_[c], (*m.windowLight)[c]);
    // As the black reading: consecutive frames only, a channel the LED lights in both.
    if (lastWindowLight_ && lastWindowSequence_ && sequence == *lastWindowSequence_ + 1)
      for (int c = 0; c < 3; ++c)
        if ((*lastWindowLight_)[c] > 0.0 && (*m.windowLight)[c] > 0.0)
          keepLatest(windowSteps_[c], (*m.windowLight)[c] / (*lastWindowLight_)[c] - 1.0);
    lastWindowLight_ = *m.windowLight;
    lastWindowSequence_ = sequence;
  }
}

control::DecodingCheckView DecodingWatch::view() const {
  control::DecodingCheckView view;
  view.blackReading = median(readings_);
  if (const auto step = meanAndSigmas(steps_)) {
    view.blackReadingStep = step->first;
    view.blackReadingStepSigmas = step->second;
  }
  for (int c = 0; c < 3; ++c)
    if (const std::optional<double> fraction = median(atBlack_[c]);
        fraction && (!view.windowAtBlack || *fraction > *view.windowAtBlack)) {
      view.windowAtBlack = fraction;
      view.windowAtBlackChannel = kChannelNames[c];
    }
  // The channel whose light sits lowest against its own spread: the one the refusal judges.
  for (int c = 0; c < 3; ++c) {
    if (lights_[c].empty()) continue;
    const UnlitFigures figures = unlitFigures(lights_[c]);
    // Ties (a spread of 0 caps the figure): the channel most often at or below 0.
    if (!view.windowUnlitSigmas || figures.medianSigmas < *view.windowUnlitSigmas ||
        (figures.medianSigmas == *view.windowUnlitSigmas &&
         figures.atOrBelowZero > *view.windowUnlit)) {
      view.windowUnlit = figures.atOrBelowZero;
      view.windowUnlitAtZero = figures.atZero;
      view.windowUnlitSigmas = figures.medianSigmas;
      view.windowUnlitMeanSigmas = figures.trimmedMeanSigmas;
      view.windowUnlitChannel = kChannelNames[c];
    }
  }
  for (int c = 0; c < 3; ++c)
    if (const auto step = meanAndSigmas(windowSteps_[c]);
        step && (!view.windowStepSigmas || step->second > *view.windowStepSigmas)) {
      view.windowStep = step->first;
      view.windowStepSigmas = step->second;
      view.windowStepChannel = kChannelNames[c];
    }
  return view;
}

std::vector<std::string> DecodingWatch::warnings() const {
  std::vector<std::string> out;
  if (!eightBit_) return out;
  const control::DecodingCheckView figures = view();
  if (steps_.size() >= kMinSamples && figures.blackReadingStep && figures.blackReadingStepSigmas &&
      std::abs(*figures.blackReadingStep) > kMaxBlackReadingStep &&
      *figures.blackReadingStepSigmas > kMinStepSigmas) {
    char sigmas[32];
    std::snprintf(sigmas, sizeof sigmas, "%.1f", *figures.blackReadingStepSigmas);
    out.push_back("decoding: the black patch's reading against the white references steps by " +
                  percent(*figures.blackReadingStep) + " on average from a frame to the next (" +
                  sigmas + " standard errors; more than " + percent(kMaxBlackReadingStep) +
                  " is a curve, not noise): the camera's tone curve changes from frame to frame "
                  "(adaptive contrast: a Raspberry Pi's rpi.contrast ce_enable), so no measured "
                  "curve decodes its frames and this sweep's samples cannot be trusted. Use RAW "
                  "(camera_raw = auto or on), slicecap's tuning file (tuning_file = auto), or a "
                  "camera whose processing is fixed");
  }
  std::size_t windowSteps = 0;
  for (const auto& channel : windowSteps_) windowSteps = std::max(windowSteps, channel.size());
  if (windowSteps >= kMinSamples && figures.windowStep && figures.windowStepSigmas &&
      std::abs(*figures.windowStep) > kMaxWindowStep && *figures.windowStepSigmas > kMinStepSigmas) {
    char sigmas[32];
    std::snprintf(sigmas, sizeof sigmas, "%.1f", *figures.windowStepSigmas);
    out.push_back("decoding: the window's " + *figures.windowStepChannel +
                  " light against the white references steps by " + percent(*figures.windowStep) +
                  " on average from a frame to the next (" + sigmas +
                  " standard errors; more than " + percent(kMaxWindowStep) +
                  " is a curve, not noise): the camera stretches its tone curve from frame to frame "
                  "(adaptive contrast: a Raspberry Pi's rpi.contrast ce_enable), which moves the "
                  "window's dark channels against the whites, so this sweep's samples cannot be "
                  "trusted. Use RAW (camera_raw = auto or on), slicecap's tuning file (tuning_file "
                  "= auto), or a camera whose processing is fixed");
  }
  if (atBlack_[0].size() >= kMinSamples && figures.windowAtBlack &&
      *figures.windowAtBlack > kMaxWindowAtBlack)
    out.push_back("decoding: " + percent(*figures.windowAtBlack) + " of the window's " +
                  *figures.windowAtBlackChannel +
                  " pixels are at code 0 with the LED on (more than " + percent(kMaxWindowAtBlack) +
                  "; noise at black leaves about half): the camera's colour processing takes "
                  "that channel below black (a colour matrix mixing the channels, a Raspberry "
                  "Pi's rpi.ccm), so this sweep's samples cannot be trusted. Use RAW (camera_raw "
                  "= auto or on) or slicecap's tuning file (tuning_file = auto: an identity "
                  "matrix)");
  if (std::optional<std::string> refused = refusal()) out.push_back(std::move(*refused));
  return out;
}

std::optional<std::string> DecodingWatch::refusal() const {
  if (!eightBit_ || lights_[0].size() < kMinRefusalSamples) return std::nullopt;
  // Each channel judged on its own: the view names the lowest, and a pinned channel may be
  // another.
  for (int c = 0; c < 3; ++c) {
    const UnlitFigures figures = unlitFigures(lights_[c]);
    const bool medianBelow = figures.medianSigmas < -kMinBelowBlackSigmas;
    const bool meanBelow =
        figures.trimmedMeanSigmas && *figures.trimmedMeanSigmas < -kMinMeanBelowBlackSigmas;
    if (!medianBelow && !meanBelow && !(figures.atZero > kMaxWindowPinned)) continue;
    char sigmas[32];
    std::snprintf(sigmas, sizeof sigmas, "%.1f",
                  medianBelow ? -figures.medianSigmas : -figures.trimmedMeanSigmas.value_or(0.0));
    const std::string what =
        medianBelow ? std::string("its median is ") + sigmas +
                          " standard errors below 0 (more than " +
                          std::to_string(int(kMinBelowBlackSigmas)) + ")"
        : meanBelow ? std::string("its mean (a highlight's samples left out) is ") + sigmas +
                          " standard errors below 0 (more than " +
                          std::to_string(int(kMinMeanBelowBlackSigmas)) + ")"
                    : "it is exactly 0 in " + percent(figures.atZero) + " (more than " +
                          percent(kMaxWindowPinned) + ": the clip pinned it)";
    return std::string("decoding broken: the window's ") + kChannelNames[c] +
           " light from the LED sits below black over the latest " +
           std::to_string(lights_[c].size()) + " samples: " + what + ", at or below 0 in " +
           percent(figures.atOrBelowZero) +
           " (the LED only adds light: an honest dark channel scatters around a mean at or above "
           "0): the camera's processing lost that channel below black (a colour matrix mixing the "
           "channels, a Raspberry Pi's rpi.ccm; a tone curve the fit misses), and no decoding "
           "brings it back. Use RAW (camera_raw = auto or on) or slicecap's tuning file "
           "(tuning_file = auto: an identity matrix), then sweep the slice again";
  }
  return std::nullopt;
}

std::optional<std::string> DecodingWatch::unlitVerdict(RefusalPolicy policy) const {
  if (lights_[0].empty()) return std::nullopt;
  if (!eightBit_) return "not judged: a linear (RAW) stream keeps the light below black";
  if (lights_[0].size() < kMinRefusalSamples)
    return "not judged yet: " + std::to_string(lights_[0].size()) + " of the " +
           std::to_string(kMinRefusalSamples) + " samples a judgement needs";
  if (!refusal()) return "kept: no channel sits below black";
  switch (policy) {
    case RefusalPolicy::Refuse:
      return "refused as the run ends: a channel sits below black";
    case RefusalPolicy::Refused:
      return "refused: a channel sat below black; the run's samples and texture frames were set "
             "aside";
    case RefusalPolicy::WarnOnly:
      return "a channel sits below black; kept, as refuse_broken_decoding = false";
    case RefusalPolicy::NoSession:
      break;
  }
  return "a channel sits below black; not refused: no session was open as the run began, so "
         "none of its samples were recorded";
}

}  // namespace slicecap::daemon
