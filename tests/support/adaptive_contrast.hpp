// The Raspberry Pi's adaptive contrast as a camera model's tone curve stretched per frame: for
// the response gate's tests (capture and daemon) and its figures.
#pragma once

#include <algorithm>
#include <utility>
#include <vector>

#include "slicecap/core/tone_curve.hpp"
#include "slicecap/hal/model_camera.hpp"

namespace slicecap::test {

// The adaptive contrast of the Raspberry Pi's IPA, as the IMX708 tuning files enable it
// (rpi.contrast ce_enable 1; raspberrypi/libcamera src/ipa/rpi/controller/rpi/contrast.cpp,
// computeStretchCurve with Contrast::read's defaults): per frame, the luminance histogram's 1 %
// point is pulled down to 0.015 of full scale (from at most 500/65536 above it), its median kept,
// its 95 % point pushed up to 0.95 (from at most 2000/65536 below it), a piecewise-linear stretch
// of linear light composed before the gamma curve. Points that do not increase are skipped, as
// the IPA's Pwl::append skips them. `strength` multiplies the two limits (lo_max, hi_max): 1 is
// the IMX708 files' defaults, 2 the Pi 5 IMX219 file's lo_max of 1000; more stands for an
// adaptive contrast that is not held to them (a webcam's, or a tuning that raises them).
struct HistogramPoints {
  double lo = 0.0, median = 0.0, hi = 0.0;  // fractions of full scale
};

inline ToneCurve stretchedCurve(const ToneCurve& gamma, const HistogramPoints& h, double strength) {
  constexpr double kLoLevel = 0.015, kHiLevel = 0.95;
  const double kLoMax = strength * 500.0 / 65536, kHiMax = strength * 2000.0 / 65536;
  const double histLo = std::max(kLoLevel, std::min({1.0, h.lo, kLoLevel + kLoMax}));
  const double histHi = std::min(kHiLevel, std::max({0.0, h.hi, kHiLevel - kHiMax}));
  std::vector<std::pair<double, double>> stretch{{0.0, 0.0}};
  const auto append = [&stretch](double x, double y) {
    if (x > stretch.back().first + 1e-9) stretch.emplace_back(x, y);
  };
  append(histLo, kLoLevel);
  append(h.median, h.median);
  append(histHi, kHiLevel);
  append(1.0, 1.0);
  const auto stretched = [&stretch](double x) {
    for (std::size_t i = 1; i < stretch.size(); ++i)
      if (x <= stretch[i].first) {
        const auto [x0, y0] = stretch[i - 1];
        const auto [x1, y1] = stretch[i];
        return y0 + (y1 - y0) * (x - x0) / (x1 - x0);
      }
    return 1.0;
  };
  std::vector<std::pair<double, double>> points;
  for (int i = 0; i <= 1024; ++i) {
    const double x = i / 1024.0;
    points.emplace_back(x, gamma.encode(stretched(x)));
  }
  return ToneCurve("imx708-adaptive", std::move(points));
}

// The frame's luminance histogram points at `scale` (exposure s x gain): the mean of the three
// channels after the colour gains, clipped at full scale, as the ISP's statistics see it.
inline HistogramPoints histogramAt(const hal::SceneLight& light, const hal::SensorModel& model,
                                   double scale) {
  std::vector<double> luminance;
  luminance.reserve(light.ledRate.size() / 3);
  for (std::size_t p = 0; p + 2 < light.ledRate.size(); p += 3) {
    double sum = 0.0;
    for (int c = 0; c < 3; ++c)
      sum += model.colourGains[c] * (light.ledRate[p + c] + double(light.ambientRate[p + c]));
    luminance.push_back(std::min(1.0, scale * sum / 3.0));
  }
  const auto quantile = [&luminance](double q) {
    const auto at = luminance.begin() + std::ptrdiff_t(q * double(luminance.size() - 1));
    std::nth_element(luminance.begin(), at, luminance.end());
    return *at;
  };
  return {quantile(0.01), quantile(0.5), quantile(0.95)};
}

}  // namespace slicecap::test
