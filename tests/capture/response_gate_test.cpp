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

#include "../support/adaptive_contrast.hpp"
#include "../support/bracket_rig.hpp"
#include "../support/curve_error.hpp"
#include "slicecap/capture/response_curve.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {
namespace {

using test::histogramAt;
using test::stretchedCurve;

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
