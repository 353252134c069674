// The mean of a target area's pixels and the variance the sensor's noise model gives it.
#include "slicecap/capture/area_reading.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "censored_mean.hpp"

namespace slicecap::capture {
namespace {

double srgbDecode(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

double srgbEncode(double v) {
  v = std::clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

// The area's outline in pixels: each edge sampled so that lens distortion bends it. Empty when
// a point is behind the camera.
std::vector<Eigen::Vector2d> outlinePx(const vision::Pose& pose, const vision::CameraModel& camera,
                                       const vision::RectMm& r) {
  constexpr int kPerEdge = 8;
  const std::array<Eigen::Vector2d, 4> corners = {Eigen::Vector2d{r.xMinMm, r.yMinMm},
                                                  Eigen::Vector2d{r.xMaxMm, r.yMinMm},
                                                  Eigen::Vector2d{r.xMaxMm, r.yMaxMm},
                                                  Eigen::Vector2d{r.xMinMm, r.yMaxMm}};
  std::vector<Eigen::Vector2d> outline;
  for (int e = 0; e < 4; ++e)
    for (int k = 0; k < kPerEdge; ++k) {
      const Eigen::Vector2d p =
          corners[e] + (corners[(e + 1) % 4] - corners[e]) * (double(k) / kPerEdge);
      const auto px = camera.project(pose.toCamera({p.x(), p.y(), 0.0}));
      if (!px) return {};
      outline.push_back(*px);
    }
  return outline;
}

// The outline's vertical extent and its orientation (the sign of twice its area).
struct OutlineExtent {
  double minY = 1e30, maxY = -1e30, signedArea = 0.0;
};

// The outline's extent; nullopt when part of the area is out of the image.
std::optional<OutlineExtent> extentInImage(const std::vector<Eigen::Vector2d>& outline,
                                           const Image& im) {
  OutlineExtent extent;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Eigen::Vector2d& a = outline[i];
    const Eigen::Vector2d& b = outline[(i + 1) % outline.size()];
    if (a.x() < -0.5 || a.y() < -0.5 || a.x() > im.width - 0.5 || a.y() > im.height - 0.5)
      return std::nullopt;  // part of the area is out of the image
    extent.minY = std::min(extent.minY, a.y()), extent.maxY = std::max(extent.maxY, a.y());
    extent.signedArea += a.x() * b.y() - b.x() * a.y();
  }
  return extent;
}

// Each edge as a half-plane n . p >= offset (n its unit inward normal, moved in by the inset).
struct HalfPlane {
  Eigen::Vector2d normal;
  double offset;
};

std::vector<HalfPlane> insetHalfPlanes(const std::vector<Eigen::Vector2d>& outline,
                                       double signedArea, double insetPx) {
  std::vector<HalfPlane> edges;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Eigen::Vector2d d = outline[(i + 1) % outline.size()] - outline[i];
    if (d.norm() < 1e-12) continue;
    Eigen::Vector2d n = signedArea > 0 ? Eigen::Vector2d(-d.y(), d.x()) : Eigen::Vector2d(d.y(), -d.x());
    n.normalize();
    edges.push_back({n, n.dot(outline[i]) + insetPx});
  }
  return edges;
}

// The pixel columns x0..x1 of row y inside every half-plane (empty when x1 < x0).
inline std::pair<int, int> rowRun(const std::vector<HalfPlane>& edges, int y, int widthPx) {
  // The row's run inside every half-plane: n.x x >= offset - n.y y.
  double xLo = -0.5, xHi = widthPx - 0.5;
  for (const HalfPlane& h : edges) {
    const double rhs = h.offset - h.normal.y() * y;
    if (std::abs(h.normal.x()) < 1e-12) {
      if (rhs > 0) xLo = xHi + 1;  // the row lies outside this edge
    } else if (h.normal.x() > 0) {
      xLo = std::max(xLo, rhs / h.normal.x());
    } else {
      xHi = std::min(xHi, rhs / h.normal.x());
    }
  }
  const int x0 = std::max(0, static_cast<int>(std::ceil(xLo)));
  const int x1 = std::min(widthPx - 1, static_cast<int>(std::floor(xHi)));
  return {x0, x1};
}

// Per channel, the sum of the area's linear pixel values and of their variances (sensor noise
// and quantisation).
struct PixelSums {
  std::array<double, 3> sum{}, variance{};
  int count = 0;
  /// 8-bit frames: what the pixels say about a clip at black (censored_mean.hpp).
  std::array<ClippedPixels, 3> clipped{};
};

PixelSums sumAreaPixels(const hal::Frame& frame, const std::vector<HalfPlane>& edges,
                        const OutlineExtent& extent, const AreaSpec& area, const SensorNoise& noise,
                        const CodeTable& codes, double gain, AreaReading& reading) {
  const Image& im = frame.image;
  const bool srgb = frame.encoding == PixelEncoding::Srgb8;
  const double fullScale = srgb ? 255.0 : 65535.0;
  const double clipRaw = area.clipFraction * fullScale;
  const double step16 = 1.0 / 65535.0;
  PixelSums sums;
  for (ClippedPixels& c : sums.clipped) {
    c.zeroTop = 0.5 * (codes[0] + codes[1]);
    c.noiseSigma = std::sqrt(noise.pixelVariance(0.0, gain));
  }
  const int y0 = std::max(0, static_cast<int>(std::ceil(extent.minY)));
  const int y1 = std::min(im.height - 1, static_cast<int>(std::floor(extent.maxY)));
  for (int y = y0; y <= y1; ++y) {
    const auto [x0, x1] = rowRun(edges, y, im.width);
    for (int x = x0; x <= x1; ++x) {
      ++sums.count;
      for (int c = 0; c < 3; ++c) {
        const std::uint16_t raw = im.at(x, y, im.channels >= 3 ? c : 0);
        if (raw >= clipRaw) reading.clipped = true;
        double v, step;
        if (srgb) {
          const int code = std::min<int>(raw, 255);
          // The linear width of the values the code stands for, half a code either side.
          v = codes[std::uint16_t(code)];
          step = (codes[std::uint16_t(std::min(code + 1, 255))] -
                  codes[std::uint16_t(std::max(code - 1, 0))]) / 2.0;
        } else {
          v = hal::linear16Value(raw, frame.black16), step = step16;
        }
        sums.sum[c] += v;
        sums.variance[c] += noise.pixelVariance(v, gain) + step * step / 12.0;
        if (srgb) {
          ClippedPixels& clip = sums.clipped[c];
          ++clip.count;
          clip.atZero += raw == 0;
          clip.sum += v;
          clip.sumSquares += v * v;
        }
      }
    }
  }
  return sums;
}

// The per-unit-exposure mean and the variance of that mean, into `reading`.
void storeMeanAndVariance(const PixelSums& sums, const hal::Frame& frame, const SensorNoise& noise,
                          double gain, AreaReading& reading) {
  const int count = sums.count;
  const double scale = frame.metadata.exposureUs * frame.metadata.gain;
  const double perUnit = scale > 0 ? 1.0 / scale : 1.0;
  for (int c = 0; c < 3; ++c) {
    // An 8-bit frame's pixels near black came clipped at 0: the mean of the light they saw.
    const double mean = unclippedMean(sums.clipped[c]).value_or(sums.sum[c] / count);
    // What noise too small to dither leaves of the quantisation in a mean: a bias that does not
    // shrink with the pixel count.
    const double step = quantisationStep(frame.encoding, mean);
    const double sigma2 = noise.pixelVariance(mean, gain);
    const double bias =
        step / std::numbers::pi * std::exp(-2.0 * std::numbers::pi * std::numbers::pi * sigma2 /
                                           (step * step));
    reading.mean[c] = mean * perUnit;
    reading.atBlack[c] = double(sums.clipped[c].atZero) / count;
    reading.variance[c] =
        (sums.variance[c] / (double(count) * count) + bias * bias) * perUnit * perUnit;
  }
}

}  // namespace

bool SensorNoise::isValid(std::string* error) const {
  const auto fail = [&](const char* text) {
    if (error) *error = text;
    return false;
  };
  if (!(std::isfinite(readNoise) && readNoise >= 0.0))
    return fail("sensor noise: readNoise must be finite and not negative");
  if (!(std::isfinite(fullWellElectrons) && fullWellElectrons >= 0.0))
    return fail("sensor noise: fullWellElectrons must be finite and not negative");
  return true;
}

double SensorNoise::pixelVariance(double v, double gain) const {
  const double shot = fullWellElectrons > 0.0 ? std::max(v, 0.0) * gain / fullWellElectrons : 0.0;
  return readNoise * readNoise + shot;
}

double quantisationStep(PixelEncoding encoding, double v) {
  if (encoding != PixelEncoding::Srgb8) return 1.0 / 65535.0;
  const double code = srgbEncode(v) * 255.0;
  return srgbDecode((code + 0.5) / 255.0) - srgbDecode((code - 0.5) / 255.0);
}

AreaReading readArea(const hal::Frame& frame, const vision::Pose& pose,
                     const vision::CameraModel& camera, const AreaSpec& area,
                     const SensorNoise& noise, const CodeTable& codes) {
  AreaReading reading;
  const std::vector<Eigen::Vector2d> outline = outlinePx(pose, camera, area.rectMm);
  if (outline.empty()) return reading;
  const std::optional<OutlineExtent> extent = extentInImage(outline, frame.image);
  if (!extent) return reading;
  const std::vector<HalfPlane> edges = insetHalfPlanes(outline, extent->signedArea, area.insetPx);
  const double gain = frame.metadata.gain > 0 ? frame.metadata.gain : 1.0;
  const PixelSums sums = sumAreaPixels(frame, edges, *extent, area, noise, codes, gain, reading);
  if (sums.count == 0) return reading;
  storeMeanAndVariance(sums, frame, noise, gain, reading);
  reading.pixels = sums.count;
  reading.inside = true;
  return reading;
}

}  // namespace slicecap::capture
