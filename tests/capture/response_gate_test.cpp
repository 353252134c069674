// The response curve's residual gate (issue 44): the model camera's bracket through its fixed
// IMX708 curve is accepted, the same bracket through a curve the Raspberry Pi's adaptive contrast
// stretches per frame is refused with the figure. Prints both residuals
// (docs/results/2026-12-06-response-gate.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>

#include "../support/bracket_rig.hpp"
#include "../support/curve_error.hpp"
#include "slicecap/capture/response_curve.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {
namespace {

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

ToneCurve stretchedCurve(const ToneCurve& gamma, const HistogramPoints& h, double strength) {
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
HistogramPoints histogramAt(const hal::SceneLight& light, const hal::SensorModel& model,
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

struct GateRig {
  std::shared_ptr<const sim::FrameRenderer> renderer = std::make_shared<sim::FrameRenderer>(
      vision::defaultSimulatedCamera(), vision::defaultTarget(), sim::loadMaterial("matte-paint"),
      sim::RigParams::ideal());
  std::shared_ptr<test::StillScene> scene =
      std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
};

// The strength the refusal test uses (the figures: docs/results/2026-12-06-response-gate.md).
constexpr double kRefusedStrength = 8.0;

const GateRig& gateRig() {
  static const GateRig rig;
  return rig;
}

// The bracket the model camera takes when its tone curve is `fixed` stretched per frame at
// `strength` (0: not stretched), one camera model per frame; `metered` gets the metered frame's
// own curve (the curve every sweep frame near that exposure is decoded against).
std::vector<hal::Frame> stretchedBracket(double strength, ToneCurve* metered,
                                         double noiseScale = 1.0) {
  hal::SensorModel fixed;
  fixed.readNoise *= noiseScale;  // a noisier sensor: more read noise, fewer electrons
  fixed.fullWellElectrons /= noiseScale * noiseScale;
  test::BracketRig first(gateRig().scene, fixed);
  const double meteredUs = first.meteredExposureUs();
  const std::vector<hal::ExposureSetting> settings = BracketPlan{}.settings({meteredUs, 1.0});
  if (strength == 0.0) {
    *metered = fixed.tone;
    return first.take(settings);
  }
  std::vector<hal::Frame> bracket;
  for (const hal::ExposureSetting& setting : settings) {
    const double scale = setting.exposureUs * 1e-6 * setting.gain.value_or(1.0);
    hal::SensorModel model = fixed;
    model.tone = stretchedCurve(fixed.tone, histogramAt(gateRig().scene->light(), fixed, scale),
                                strength);
    if (std::abs(scale * 1e6 / meteredUs - 1.0) < 1e-6) *metered = model.tone;
    test::BracketRig rig(gateRig().scene, model);
    bracket.push_back(rig.take({setting}).front());
  }
  return bracket;
}

// The fit's residual, its error against the metered frame's curve over the references' range
// (docs/linear-light.md: linear 0.0068..0.33, relative to the white), and whether the gate
// refused it (the figures of docs/results/2026-12-06-response-gate.md).
struct GateFigures {
  double rmsLogResidual = 0.0, curveError = 0.0;
  bool refused = false;
};

GateFigures gateFigures(double strength, double noiseScale = 1.0) {
  ToneCurve metered = ToneCurve::linear();
  const std::vector<hal::Frame> bracket = stretchedBracket(strength, &metered, noiseScale);
  ResponseFitParams params;
  params.cameraName = "model";
  params.maxRmsLogResidual = 1e9;  // the fit as it would be without the gate
  const ResponseFit fit =
      fitResponse(bracket, gateRig().renderer->target(), gateRig().renderer->camera(), params);
  GateFigures figures{fit.rmsLogResidual,
                      test::largestRelativeError(fit.curve, metered, 0.0068, 0.33), false};
  try {
    checkResponseResidual(fit, ResponseFitParams{}, "model");
  } catch (const ResponseCurveMisfit& misfit) {
    figures.refused = true;
    EXPECT_NE(std::string(misfit.what()).find("RMS residual"), std::string::npos);
  }
  std::printf("[ gate ] noise x%g, stretch x%g: RMS residual %.2f %%, curve error %.2f %% -> %s\n",
              noiseScale, strength, 100.0 * figures.rmsLogResidual, 100.0 * figures.curveError,
              figures.refused ? "refused" : "accepted");
  return figures;
}

TEST(ResponseGate, TheModelsFixedCurveIsAccepted) {
  ToneCurve metered = ToneCurve::linear();
  ResponseFitParams params;
  params.cameraName = "model";
  // fitResponse, gate included, takes the model's bracket through its fixed IMX708 curve.
  const ResponseFit fit = fitResponse(stretchedBracket(0.0, &metered),
                                      gateRig().renderer->target(), gateRig().renderer->camera(),
                                      params);
  EXPECT_LT(fit.rmsLogResidual, params.maxRmsLogResidual);
}

TEST(ResponseGate, ACurveStretchedPerFrameIsRefusedWithItsFigure) {
  const GateFigures stretched = gateFigures(kRefusedStrength);
  EXPECT_TRUE(stretched.refused) << "RMS residual " << stretched.rmsLogResidual;
  // What the gate spares the sweep: a curve that far off.
  EXPECT_GT(stretched.curveError, 0.02);
}

// The figures at every strength (SLICECAP_GATE_STRENGTHS="0 1 2 4 8 16", 0: the fixed curve),
// the sensor's noise scaled by SLICECAP_GATE_NOISE_SCALE (default 1); scripts/response-gate.
TEST(ResponseGate, FiguresAtEachStrength) {
  const char* strengths = std::getenv("SLICECAP_GATE_STRENGTHS");
  if (!strengths) GTEST_SKIP() << "SLICECAP_GATE_STRENGTHS not set (scripts/response-gate sets it)";
  const char* noise = std::getenv("SLICECAP_GATE_NOISE_SCALE");
  const double noiseScale = noise ? std::atof(noise) : 1.0;
  std::istringstream in(strengths);
  for (double strength = 0.0; in >> strength;) {
    try {
      gateFigures(strength, noiseScale);
    } catch (const ResponseFitError& error) {  // a bracket too far off for any fit
      std::printf("[ gate ] noise x%g, stretch x%g: not fitted: %s\n", noiseScale, strength,
                  error.what());
    }
  }
}

}  // namespace
}  // namespace slicecap::capture
