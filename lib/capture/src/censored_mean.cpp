// A processed frame's dark pixels arrive clipped at black: an ISP works on unsigned samples after
// its black level block (the Pi 5's back end: struct pisp_bla_config, Linux uapi
// media/raspberrypi/pisp_be_config.h) and its RGB888 / YUV420 outputs put black at code 0, so a
// pixel that noise took below black leaves as 0. The plain mean of an area near black then reads
// about 0.4 sigma too bright; an LED-off frame subtracted from every sample carries that into the
// samples of a dark channel (issue 44: R -17 % on satin-blue-45's processed stream).
#include "censored_mean.hpp"

#include <cmath>

namespace slicecap::capture {
namespace {

// How far the Gaussian's spread may exceed the noise model's at black: a processed stream's
// colour gains (the camera model's red 1.9) and its processing raise the sensor's noise.
constexpr double kMaxNoiseFactor = 4.0;

double normalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }
double normalPdf(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * M_PI); }

// The x with normalCdf(x) = p, by bisection (a handful of calls per frame).
double normalQuantile(double p) {
  double lo = -9.0, hi = 9.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (normalCdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

std::optional<double> unclippedMean(const ClippedPixels& pixels) {
  if (pixels.count < 2 || pixels.atZero == 0 || pixels.atZero >= pixels.count) return std::nullopt;
  const double n = pixels.count, p0 = pixels.atZero / n, t = pixels.zeroTop;
  const double mean = pixels.sum / n, meanSquare = pixels.sumSquares / n;
  // X ~ N(mu, sigma); a pixel is 0 when X < t, else X: P(0) = Phi(a) with a = (t - mu) / sigma,
  // E[Y] = mu (1 - p0) + sigma phi(a).
  const double a = normalQuantile(p0);
  const double tail = 1.0 - p0, density = normalPdf(a);
  const double sigma = (mean - t * tail) / (density - a * tail);
  if (!(sigma > 0.0) || !std::isfinite(sigma)) return std::nullopt;
  // A spread far beyond the noise is the scene's (a dark and a bright part), not a clip's.
  if (pixels.noiseSigma > 0.0 && sigma > kMaxNoiseFactor * pixels.noiseSigma) return std::nullopt;
  const double mu = t - a * sigma;
  // The same Gaussian's E[Y^2] = (mu^2 + sigma^2)(1 - p0) + (mu + t) sigma phi(a): an area that
  // is not one clipped Gaussian (dark and bright parts) spreads far more, and is left alone.
  const double expected = (mu * mu + sigma * sigma) * tail + (mu + t) * sigma * density;
  const double variance = meanSquare - mean * mean;
  const double expectedVariance = expected - mean * mean;
  if (!(expectedVariance > 0.0) || std::abs(variance / expectedVariance - 1.0) > 0.35)
    return std::nullopt;
  return mu;
}

}  // namespace slicecap::capture
