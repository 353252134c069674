// The room light's flicker from the rows of LED-off frames, and its level against the LED's.
#include "slicecap/hwcheck/room_light_check.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "formatted.hpp"
#include "slicecap/hwcheck/hardware_check_error.hpp"

namespace slicecap::hwcheck {
namespace {

// Rows darker than this (fraction of full scale, R+G+B summed) say nothing about the flicker.
constexpr double kMinRowLevel = 0.01;
// A fit explaining less of the rows' spread than this is noise.
constexpr double kMinExplained = 0.2;
// A flicker shallower than this is reported as none (it costs the capture nothing measurable).
constexpr double kMinDepth = 0.01;

// The rows of one frame: mean over the row of R+G+B, decoded.
std::vector<double> rowLevelsOf(const hal::Frame& frame, const capture::CodeTable& codes) {
  const Image& image = frame.image;
  std::vector<double> rows(std::size_t(std::max(image.height, 0)), 0.0);
  const bool linear = frame.encoding != PixelEncoding::Srgb8;
  for (int y = 0; y < image.height; ++y) {
    const std::uint16_t* row = image.samples.data() + std::size_t(y) * image.width * 3;
    double sum = 0.0;
    // A RAW frame's decode keeps its black above 0 (frame.black16): taken off, or the pedestal
    // would read as steady room light and thin the flicker's depth.
    for (int k = 0; k < image.width * 3; ++k)
      sum += linear ? hal::linear16Value(row[k], frame.black16) : codes[row[k]];
    rows[std::size_t(y)] = sum / image.width;
  }
  return rows;
}

// The regression of the rows' relative deviations on the flicker's cos and sin at `hz`, each
// less its mean over the frames at that row (the scene's row means absorb that part).
struct Regression {
  double a = 0.0, b = 0.0;  // cos and sin coefficients
  double explained = 0.0;   // explained sum of squares
  double regressorEnergy = 0.0;
};

Regression regress(const std::vector<std::vector<double>>& relative,
                   const std::vector<RowProfile>& frames, const std::vector<char>& usable,
                   double lineTimeUs, double exposureUs, double hz) {
  const std::size_t rows = usable.size(), n = frames.size();
  double scc = 0, sss = 0, scs = 0, scy = 0, ssy = 0;
  std::vector<double> c(n), s(n);
  for (std::size_t r = 0; r < rows; ++r) {
    if (!usable[r]) continue;
    double meanC = 0, meanS = 0;
    for (std::size_t f = 0; f < n; ++f) {
      const double midUs = frames[f].row0StartUs + double(r) * lineTimeUs + exposureUs / 2;
      const double cycles = hz * midUs * 1e-6;
      const double radians = 2.0 * std::numbers::pi * (cycles - std::floor(cycles));
      c[f] = std::cos(radians);
      s[f] = std::sin(radians);
      meanC += c[f];
      meanS += s[f];
    }
    meanC /= double(n);
    meanS /= double(n);
    for (std::size_t f = 0; f < n; ++f) {
      const double x = c[f] - meanC, z = s[f] - meanS, y = relative[f][r];
      scc += x * x;
      sss += z * z;
      scs += x * z;
      scy += x * y;
      ssy += z * y;
    }
  }
  Regression out;
  out.regressorEnergy = scc + sss;
  const double det = scc * sss - scs * scs;
  if (!(det > 1e-12 * (scc + sss) * (scc + sss)) || det <= 0.0) return out;
  out.a = (sss * scy - scs * ssy) / det;
  out.b = (scc * ssy - scs * scy) / det;
  out.explained = out.a * scy + out.b * ssy;
  return out;
}

}  // namespace

FlickerFit fitFlicker(const std::vector<RowProfile>& frames, double lineTimeUs, double exposureUs) {
  FlickerFit fit;
  if (frames.size() < 3) {
    fit.problem = "fewer than 3 LED-off frames";
    return fit;
  }
  const std::size_t rows = frames.front().rowLevels.size();
  for (const RowProfile& f : frames)
    if (f.rowLevels.size() != rows) {
      fit.problem = "the frames differ in size";
      return fit;
    }
  // The scene per row: its mean over the frames; the rows' deviations relative to it.
  std::vector<char> usable(rows, 0);
  std::vector<std::vector<double>> relative(frames.size(), std::vector<double>(rows, 0.0));
  double total = 0.0;
  int usableRows = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    double mean = 0.0;
    for (const RowProfile& f : frames) mean += f.rowLevels[r];
    mean /= double(frames.size());
    if (mean < kMinRowLevel) continue;
    usable[r] = 1;
    ++usableRows;
    for (std::size_t f = 0; f < frames.size(); ++f) {
      relative[f][r] = frames[f].rowLevels[r] / mean - 1.0;
      total += relative[f][r] * relative[f][r];
    }
  }
  if (usableRows < 16) {
    fit.problem = "the LED-off frames are black: no room light to measure";
    return fit;
  }
  // A coarse search, then a fine one around the best.
  const auto best = [&](double fromHz, double toHz, double stepHz) {
    double bestHz = 0.0;
    Regression bestFit;
    for (double hz = fromHz; hz <= toHz + 1e-9; hz += stepHz) {
      const Regression r = regress(relative, frames, usable, lineTimeUs, exposureUs, hz);
      if (r.explained > bestFit.explained) {
        bestFit = r;
        bestHz = hz;
      }
    }
    return std::pair{bestHz, bestFit};
  };
  auto [coarseHz, coarse] = best(40.0, 250.0, 0.5);
  auto [hz, found] = best(std::max(40.0, coarseHz - 0.5), coarseHz + 0.5, 0.02);
  fit.explained = total > 0.0 ? found.explained / total : 0.0;
  // The exposure's attenuation of a sinusoid: its mean over the window.
  const double x = std::numbers::pi * hz * exposureUs * 1e-6;
  const double attenuation = x > 1e-9 ? std::abs(std::sin(x) / x) : 1.0;
  const double seenDepth = std::hypot(found.a, found.b);
  if (found.regressorEnergy <= 0.0 || hz <= 0.0) {
    fit.problem = "the frames all start at the same flicker phase";
    return fit;
  }
  if (fit.explained < kMinExplained || attenuation < 0.2 || seenDepth / attenuation < kMinDepth) {
    fit.problem = "no flicker above the noise";
    fit.depth = 0.0;
    return fit;
  }
  fit.hz = hz;
  fit.depth = std::min(1.0, seenDepth / attenuation);
  return fit;
}

namespace {

// Frames after the LED's last switch: `count` of them whose exposure began after it (frames
// queued before it are dropped), or `count` after skipping the queue when frames do not say
// when they began.
std::vector<hal::Frame> framesAfterSwitch(CheckRig& rig, std::int64_t switchUs, int count) {
  std::vector<hal::Frame> frames;
  int skippedUntimed = 0;
  for (int seen = 0; int(frames.size()) < count && seen < count + 20; ++seen) {
    std::optional<SeenFrame> next = rig.next(std::chrono::milliseconds(1000));
    if (!next) throw HardwareCheckError(rig.camera().id() + ": no frame for a second");
    const hal::FrameMetadata& m = next->frame.metadata;
    if (m.exposureStartUs) {
      if (*m.exposureStartUs <= switchUs + 1000) continue;  // the LED's guard and more
    } else if (skippedUntimed++ < 6) {
      continue;
    }
    frames.push_back(std::move(next->frame));
  }
  return frames;
}

double meanOverWhites(const std::vector<hal::Frame>& frames, const WhiteRows& whites,
                      const capture::CodeTable& codes) {
  double sum = 0.0;
  for (const hal::Frame& f : frames) sum += whites.mean(f, codes);
  return frames.empty() ? 0.0 : sum / double(frames.size());
}

}  // namespace

RoomLightResult measureRoomLight(CheckRig& rig, const WhiteRows& whites,
                                 const capture::CodeTable& codes, double exposureUs, double gain,
                                 double lineTimeUs, double framePeriodUs) {
  RoomLightResult result;
  result.framePeriodUs = framePeriodUs;
  // The ratio at the sweeps' exposure: 6 frames each way (the flicker's phase moves from frame
  // to frame, and averages out of the mean where the frame period does not hide it).
  constexpr int kRatioFrames = 6, kFlickerFrames = 12;
  rig.lockAndWait({exposureUs, gain});
  const std::int64_t onUs = rig.setLed(true);
  const double on = meanOverWhites(framesAfterSwitch(rig, onUs, kRatioFrames), whites, codes);
  const std::int64_t offUs = rig.setLed(false);
  const std::vector<hal::Frame> off = framesAfterSwitch(rig, offUs, kRatioFrames);
  const double room = meanOverWhites(off, whites, codes);
  if (on - room > 0.0) result.roomToLed = room / (on - room);
  // The flicker: 2 ms shows a 100 or 120 Hz flicker at 0.93 or 0.90 of its depth; the gain
  // brings the room light to about a third of full scale (the camera clamps it to its range).
  result.flickerExposureUs = std::min(2000.0, exposureUs);
  double flickerGain = gain;
  if (room > 0.0)
    flickerGain = std::clamp(gain * (exposureUs / result.flickerExposureUs) * (0.3 * 3.0 / room),
                             1.0, 16.0);
  const SeenFrame locked = rig.lockAndWait({result.flickerExposureUs, flickerGain});
  result.flickerExposureUs = locked.frame.metadata.exposureUs > 0 ? locked.frame.metadata.exposureUs
                                                                  : result.flickerExposureUs;
  std::vector<RowProfile> profiles;
  for (const hal::Frame& f : framesAfterSwitch(rig, offUs, kFlickerFrames)) {
    if (!f.metadata.exposureStartUs) continue;
    profiles.push_back({rowLevelsOf(f, codes), double(*f.metadata.exposureStartUs)});
  }
  result.flickerFrames = int(profiles.size());
  if (profiles.size() < 3)
    result.flicker.problem = "the frames do not say when they were exposed";
  else
    result.flicker = fitFlicker(profiles, lineTimeUs, result.flickerExposureUs);
  rig.lockAndWait({exposureUs, gain});
  return result;
}

std::optional<int> mainsOfFlicker(double flickerHz) {
  if (std::abs(flickerHz - 100.0) <= 3.0) return 50;
  if (std::abs(flickerHz - 120.0) <= 3.0) return 60;
  return std::nullopt;
}

CheckItem roomLightItem(const RoomLightResult& result, const std::string& cameraId) {
  // Room light above this fraction of the LED's: its shot noise and any change between the
  // LED-off and LED-on frames weigh on every sample (docs/real-sensors.md, "Room light").
  constexpr double kRoomToLedWarn = 0.25;
  CheckItem item{"room light", Verdict::Ok, "", ""};
  std::vector<std::string> advice;
  if (result.roomToLed) {
    item.finding = formatted("room light %.1f %% of the LED's on the white references",
                             100.0 * *result.roomToLed);
    if (*result.roomToLed > kRoomToLedWarn) {
      item.verdict = Verdict::Warn;
      advice.push_back(formatted("dim the room (or shade the target) to below %.0f %% of the LED",
                                 100.0 * kRoomToLedWarn));
    }
  } else {
    item.finding = "the room-to-LED ratio was not measured (the LED-on frames were no brighter)";
    item.verdict = Verdict::Warn;
  }
  const FlickerFit& f = result.flicker;
  if (f.hz) {
    item.finding += formatted("; it flickers at %.1f Hz, %.0f %% deep", *f.hz, 100.0 * f.depth);
    const double periodUs = 1e6 / *f.hz;
    const double periods = result.framePeriodUs / periodUs;
    const bool hidden = result.framePeriodUs > 0 && std::abs(periods - std::round(periods)) < 0.02;
    if (hidden) {
      item.finding += formatted(" (the %.1f ms frame period is %.0f of its periods: hidden)",
                                result.framePeriodUs / 1000.0, std::round(periods));
    } else if (const std::optional<int> mains = mainsOfFlicker(*f.hz)) {
      item.verdict = Verdict::Warn;
      advice.push_back(formatted("set mains_hz = %d (frames of whole flicker periods)", *mains));
    } else {
      item.verdict = Verdict::Warn;
      advice.push_back("the flicker is not a mains lamp's (100 or 120 Hz): switch that lamp off");
    }
  } else {
    item.finding += "; no flicker measured (" + f.problem + ")";
  }
  item.finding = cameraId + ": " + item.finding;
  for (const std::string& a : advice) item.advice += (item.advice.empty() ? "" : "; ") + a;
  return item;
}

}  // namespace slicecap::hwcheck
