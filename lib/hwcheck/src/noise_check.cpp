// Sensor noise from pairs of frames of the white references at several exposures.
#include "slicecap/hwcheck/noise_check.hpp"
#include "formatted.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "slicecap/hwcheck/hardware_check_error.hpp"

namespace slicecap::hwcheck {
namespace {

// Pixels above this level may clip in one frame of the pair: their difference says nothing.
constexpr double kMaxLevel = 0.85;


// One channel, linear, fraction of full scale; and its 8-bit step's quantisation variance.
struct PixelValue {
  double level = 0.0;
  double quantisation = 0.0;
};

PixelValue valueOf(const hal::Frame& frame, const capture::CodeTable& codes, int row, int col,
                   int channel) {
  const std::size_t at = (std::size_t(row) * frame.image.width + col) * 3 + std::size_t(channel);
  const int code = frame.image.samples[at];
  if (frame.encoding != PixelEncoding::Srgb8)
    return {hal::linear16Value(std::uint16_t(code), frame.black16),
            1.0 / (12.0 * 65535.0 * 65535.0)};
  const double below = codes[std::max(code - 1, 0)], above = codes[std::min(code + 1, 255)];
  const double step = (above - below) / (code > 0 && code < 255 ? 2.0 : 1.0);
  return {codes[code], step * step / 12.0};
}

NoisePoint pointOf(const hal::Frame& a, const hal::Frame& b, const WhiteRows& whites,
                   const capture::CodeTable& codes, int channel) {
  NoisePoint point;
  point.exposureUs = a.metadata.exposureUs;
  point.gain = a.metadata.gain > 0.0 ? a.metadata.gain : 1.0;
  double sumLevel = 0.0, sumDiff = 0.0, sumDiff2 = 0.0, sumQuantisation = 0.0;
  for (std::size_t row = 0; row < whites.columnsByRow.size(); ++row)
    for (int col : whites.columnsByRow[row]) {
      const PixelValue va = valueOf(a, codes, int(row), col, channel),
                       vb = valueOf(b, codes, int(row), col, channel);
      if (va.level > kMaxLevel || vb.level > kMaxLevel) continue;
      const double diff = va.level - vb.level;
      sumLevel += 0.5 * (va.level + vb.level);
      sumDiff += diff;
      sumDiff2 += diff * diff;
      sumQuantisation += 0.5 * (va.quantisation + vb.quantisation);
      ++point.pixels;
    }
  if (point.pixels < 2) return point;
  const double n = point.pixels;
  point.level = sumLevel / n;
  // The difference's variance about its mean (a light that drifted between the two frames moves
  // the mean, not the spread); one frame's is half of it.
  const double diffVariance = (sumDiff2 - sumDiff * sumDiff / n) / (n - 1.0);
  point.variance = std::max(0.5 * diffVariance - sumQuantisation / n, 0.0);
  return point;
}

}  // namespace

NoiseResult fitSensorNoise(std::vector<NoisePoint> points) {
  NoiseResult result;
  result.points = std::move(points);
  std::vector<const NoisePoint*> usable;
  for (const NoisePoint& p : result.points)
    if (p.pixels >= 50 && p.level > 0.0) usable.push_back(&p);
  if (usable.size() < 2) {
    result.problem = "fewer than two exposures left enough unclipped white pixels";
    return result;
  }
  const auto [lowest, highest] = std::minmax_element(
      usable.begin(), usable.end(), [](const NoisePoint* a, const NoisePoint* b) { return a->level < b->level; });
  if ((*highest)->level < 2.0 * (*lowest)->level) {
    result.problem = "the exposures' levels are too close to separate read from shot noise";
    return result;
  }
  // variance = a + b x (level x gain): least squares, each point weighted by 1 / variance^2
  // (a variance estimate's spread grows with it), so the dark points decide the read noise.
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const NoisePoint* p : usable) {
    const double x = p->level * p->gain, y = p->variance;
    const double w = 1.0 / std::max(y * y, 1e-24);
    sw += w, sx += w * x, sy += w * y, sxx += w * x * x, sxy += w * x * y;
  }
  const double det = sw * sxx - sx * sx;
  double slope = det > 0 ? (sw * sxy - sx * sy) / det : 0.0;
  double intercept = det > 0 ? (sy - slope * sx) / sw : 0.0;
  if (intercept < 0.0) {
    // No read noise resolvable: shot noise alone, through the origin.
    intercept = 0.0;
    slope = sxx > 0 ? sxy / sxx : 0.0;
  }
  if (!(slope > 0.0) || !std::isfinite(slope)) {
    result.problem = "the noise does not grow with the level (a denoising ISP, or a scene that "
                     "moved between the frames)";
    return result;
  }
  capture::SensorNoise noise;
  noise.readNoise = std::sqrt(intercept);
  noise.fullWellElectrons = 1.0 / slope;
  std::string why;
  if (!noise.isValid(&why)) {
    result.problem = why;
    return result;
  }
  result.noise = noise;
  return result;
}

NoiseResult measureSensorNoise(CheckRig& rig, const WhiteRows& whites, const capture::CodeTable& codes,
                               const std::vector<double>& exposuresUs) {
  std::vector<std::pair<hal::Frame, hal::Frame>> pairs;
  for (double exposureUs : exposuresUs) {
    SeenFrame first = rig.lockAndWait({exposureUs, std::nullopt});
    std::optional<SeenFrame> second = rig.next(std::chrono::milliseconds(1000));
    if (!second) throw HardwareCheckError(rig.camera().id() + ": no frame for a second");
    pairs.emplace_back(std::move(first.frame), std::move(second->frame));
  }
  // The channels differ: an ISP's white balance gains scale red's and blue's noise, a binned RAW
  // stream's green is the mean of two samples. The white-reference test reads every channel with
  // one model: the noisiest channel's (at a tenth of full scale), so that noise alone does not
  // reject dark frames.
  NoiseResult noisiest;
  double noisiestVariance = -1.0;
  std::string problems;
  for (int channel = 0; channel < 3; ++channel) {
    std::vector<NoisePoint> points;
    for (const auto& [a, b] : pairs) points.push_back(pointOf(a, b, whites, codes, channel));
    NoiseResult fit = fitSensorNoise(std::move(points));
    fit.channel = channel;
    if (!fit.noise) {
      if (problems.empty()) problems = fit.problem;
      continue;
    }
    const double variance = fit.noise->pixelVariance(0.1, 1.0);
    if (variance > noisiestVariance) {
      noisiestVariance = variance;
      noisiest = std::move(fit);
    }
  }
  if (!noisiest.noise) {
    NoiseResult none;
    none.problem = problems;
    return none;
  }
  return noisiest;
}

CheckItem sensorNoiseItem(const NoiseResult& result, const std::string& cameraId) {
  if (!result.noise)
    return {"sensor noise", Verdict::Warn,
            "not measured on " + cameraId + ": " + result.problem,
            "the capture keeps the default noise model (a small 8-bit camera module's); hold the "
            "target still under the LED and run the check again"};
  std::string levels;
  for (const NoisePoint& p : result.points)
    levels += (levels.empty() ? "" : ", ") + formatted("%.3f", p.level);
  return {"sensor noise", Verdict::Ok,
          formatted("read noise %.4f of full scale, shot noise as %.0f electrons at full scale (gain 1)",
                 result.noise->readNoise, result.noise->fullWellElectrons) +
              " (the noisiest channel, " + std::string(1, "RGB"[result.channel]) +
              "), from pairs of frames of the white references at levels " + levels,
          ""};
}

}  // namespace slicecap::hwcheck
