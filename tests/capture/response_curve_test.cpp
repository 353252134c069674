// The response fit: the solver on exact observations, then brackets rendered by the model camera
// (the IMX708's tone curve, colour gains, noise) over the virtual rig's target, against the
// model's own curve; the window / white ratio decoded through it; errors naming the input.
#include "slicecap/capture/response_curve.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "../support/bracket_rig.hpp"
#include "../support/curve_error.hpp"
#include "slicecap/capture/linear_view.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {
namespace {

// Exact mean codes (no noise, no quantisation) of areas lit from 1 to 1/3 of the brightest, with
// the white and black albedos, over the default bracket around an exposure that puts the
// brightest at 0.35: what the solver must reproduce to its knots' and penalty's accuracy. Weighted
// as measureBracket weighs the model camera's areas (about 100 pixels of ~3 codes' noise: a
// standard error of 0.3 codes).
std::vector<ResponseObservation> exactObservations(const ToneCurve& curve) {
  std::vector<ResponseObservation> out;
  // As many areas as measureBracket cuts the default target's patches into, in 3 channels.
  const std::vector<std::pair<double, int>> albedos{{0.85, 3 * 44}, {0.04, 3 * 4}};
  int area = 0;
  for (const auto& [albedo, areas] : albedos)
    for (int i = 0; i < areas; ++i, ++area) {
      const double irradiance = 0.35 / 0.85 * std::pow(1.0 / 3.0, i / (areas - 1.0));
      for (const double factor : BracketPlan{}.factors) {
        const double code = 255.0 * curve.encode(std::min(1.0, factor * irradiance * albedo));
        out.push_back({area, code, factor, albedo, code / 0.3});
      }
    }
  return out;
}


TEST(ResponseCurve, SolverRecoversSrgbAndTheImx708CurveFromExactObservations) {
  for (const ToneCurve& truth : {ToneCurve::srgb(), ToneCurve::imx708Tuning()}) {
    SCOPED_TRACE(truth.name());
    const ResponseFit fit = fitResponseCurve(exactObservations(truth), {}, "exact");
    EXPECT_EQ(fit.curve.name(), "measured");
    EXPECT_EQ(fit.exposures, 8);
    EXPECT_GT(fit.observationsLeftOut, 0);  // the brightest at x4 clip, the darkest at x1/32
    // Black at 1/3 of the light at x1: 0.35 / 0.85 * 0.04 / 3; white at x1: 0.35.
    // Exact data: what is left is the knots' interpolation and the curvature penalty, which
    // rounds the IMX708 table's kinks (1.4 % at worst at the default smoothness; sRGB, smooth,
    // 0.5 %): the solver's own share of the 2 % goal.
    EXPECT_LT(test::largestRelativeError(fit.curve, truth, 0.0055, 0.35), 0.02);
    EXPECT_LT(fit.rmsLogResidual, 0.005);
  }
}

TEST(ResponseCurve, SolverNamesWhatIsWrong) {
  std::vector<ResponseObservation> clipped = exactObservations(ToneCurve::srgb());
  for (ResponseObservation& o : clipped) o.code = 255.0;
  try {
    fitResponseCurve(clipped, {}, "cam0, 8 bracket frames");
    FAIL() << "no error";
  } catch (const ResponseFitError& error) {
    EXPECT_NE(std::string(error.what()).find("cam0, 8 bracket frames: every reference area is "
                                             "clipped"),
              std::string::npos)
        << error.what();
  }
  std::vector<ResponseObservation> few;
  for (const ResponseObservation& o : exactObservations(ToneCurve::srgb()))
    if (o.exposure >= 0.5 && o.exposure <= 1.0) few.push_back(o);
  EXPECT_THROW(fitResponseCurve(few, {}, "cam0"), ResponseFitError);
  // Brighter codes at shorter exposures: no increasing curve explains them.
  std::vector<ResponseObservation> reversed = exactObservations(ToneCurve::srgb());
  for (ResponseObservation& o : reversed) o.exposure = 1.0 / o.exposure;
  try {
    fitResponseCurve(reversed, {}, "cam0");
    FAIL() << "no error";
  } catch (const ResponseFitError& error) {
    EXPECT_NE(std::string(error.what()).find("not monotone"), std::string::npos) << error.what();
  }
}

TEST(BracketPlan, CapsTheExposureAndPutsTheRestOnTheGain) {
  std::string why;
  EXPECT_TRUE(BracketPlan{}.isValid(&why)) << why;
  EXPECT_FALSE((BracketPlan{{1.0, 0.5, 2.0, 4.0}}.isValid(&why)));
  EXPECT_NE(why.find("factor 1"), std::string::npos) << why;
  EXPECT_FALSE((BracketPlan{{0.5, 1.0}}.isValid()));
  const auto settings = BracketPlan{}.settings({16'000.0, 2.0}, 33'333.0, 16.0);
  ASSERT_EQ(settings.size(), 8u);
  EXPECT_DOUBLE_EQ(settings.front().exposureUs, 500.0);
  EXPECT_DOUBLE_EQ(*settings.front().gain, 2.0);
  EXPECT_DOUBLE_EQ(settings[6].exposureUs, 32'000.0);
  EXPECT_DOUBLE_EQ(settings.back().exposureUs, 33'333.0);
  EXPECT_NEAR(settings.back().exposureUs * *settings.back().gain, 4 * 16'000.0 * 2.0, 1e-6);
  // The camera's default gain is left alone where the exposure alone does it.
  const auto automatic = BracketPlan{}.settings({1'000.0, std::nullopt});
  EXPECT_FALSE(automatic.back().gain);
  EXPECT_DOUBLE_EQ(automatic.back().exposureUs, 4'000.0);
}

// The model camera over the still rig, with the default sensor noise.
struct ModelBracket {
  std::shared_ptr<const sim::FrameRenderer> renderer = std::make_shared<sim::FrameRenderer>(
      vision::defaultSimulatedCamera(), vision::defaultTarget(), sim::loadMaterial("matte-paint"),
      sim::RigParams::ideal());
  std::shared_ptr<test::StillScene> scene =
      std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
};

const ModelBracket& modelBracket() {
  static const ModelBracket bracket;
  return bracket;
}

// Truth and decoding over the pixels of a target rectangle: the scene's linear light at the
// exposure after the colour gains, and the frame's codes through `codes`, both per channel.
struct RegionLight {
  Rgb truth, decoded;
};
RegionLight regionLight(const hal::Frame& frame, const hal::SceneLight& light,
                        const hal::SensorModel& model, const vision::RectMm& rect,
                        const CodeTable& codes) {
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  const vision::Pose pose = test::stillPose();
  const double scale = frame.metadata.exposureUs * 1e-6 * frame.metadata.gain;
  RegionLight out;
  int n = 0;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i) {
      const double x = rect.xMinMm + (i + 0.5) * rect.widthMm() / 12;
      const double y = rect.yMinMm + (j + 0.5) * rect.heightMm() / 12;
      const auto px = camera.project(pose.toCamera({x, y, 0.0}));
      const int u = int(std::lround(px->x())), v = int(std::lround(px->y()));
      const std::size_t at = (std::size_t(v) * light.widthPx + u) * 3;
      for (int c = 0; c < 3; ++c) {
        out.truth[c] +=
            scale * model.colourGains[c] * (light.ledRate[at + c] + light.ambientRate[at + c]);
        out.decoded[c] += codes[frame.image.at(u, v, c)];
      }
      ++n;
    }
  out.truth *= 1.0 / n;
  out.decoded *= 1.0 / n;
  return out;
}

TEST(ResponseCurve, RecoversTheModelCamerasCurveAndDecodesTheWindowAgainstTheWhites) {
  const ModelBracket& setup = modelBracket();
  for (const ToneCurve& truth : {ToneCurve::imx708Tuning(), ToneCurve::srgb()}) {
    SCOPED_TRACE(truth.name());
    hal::SensorModel model;
    model.tone = truth;
    // One curve to recover: a Pi's adaptive contrast re-stretches it per frame and its colour
    // matrix mixes the channels, and the fit then misses by 37 % (RMS residual 6.2 %) with the
    // IMX708 tuning: the processed path needs them off (issue 44), which this test assumes.
    model.isp = hal::fixedModelIsp();
    test::BracketRig rig(setup.scene, model);
    const double meteredUs = rig.meteredExposureUs();
    const std::vector<hal::Frame> bracket = rig.take(BracketPlan{}.settings({meteredUs, 1.0}));
    ResponseFitParams params;
    params.cameraName = "model";
    // The figures of docs/linear-light.md at other smoothness weights.
    if (const char* weight = std::getenv("SLICECAP_RESPONSE_SMOOTHNESS"))
      params.smoothness = std::atof(weight);
    const ResponseFit fit =
        fitResponse(bracket, setup.renderer->target(), setup.renderer->camera(), params);
    SCOPED_TRACE(fit.summary());
    EXPECT_EQ(fit.exposures, 8);
    EXPECT_GE(fit.framesWithOwnPose, 6);
    // The white-to-black range at the metered exposure (x1, frame 5): the darkest channel of the
    // black patch to the brightest of the whites, from the scene's truth.
    const hal::Frame& metered = bracket[5];
    double lo = 1.0, hi = 0.0;
    for (const vision::Patch& patch : setup.renderer->target().patches) {
      const RegionLight l =
          regionLight(metered, setup.scene->light(), rig.model, patch.rect, CodeTable::srgb());
      lo = std::min(lo, l.truth.minChannel()), hi = std::max(hi, l.truth.maxChannel());
    }
    EXPECT_LT(lo, 0.02);
    EXPECT_GT(hi, 0.25);
    // Issue 27's goal, relative to the white (the curve's scale is arbitrary: only ratios are
    // read). The solver's own error on exact data is 1.4 % for this table; the noise adds little.
    const double curveError = test::largestRelativeError(fit.curve, truth, lo, hi);
    const double scaledError = test::largestRelativeError(fit.curve, truth, lo, hi, true);
    EXPECT_LT(curveError, 0.02) << "over linear " << lo << ".." << hi;
    // The window (matte paint) against the white strip left of it, at the metered exposure.
    const vision::TargetGeometry& target = setup.renderer->target();
    const vision::PointMm centre = target.window.centre();
    const vision::RectMm window{centre.xMm - 8, centre.yMm - 8, centre.xMm + 8, centre.yMm + 8};
    const vision::Patch* white = nullptr;
    for (const vision::Patch& p : target.patches)
      if (p.kind == vision::PatchKind::White && (!white || p.rect.xMaxMm < white->rect.xMaxMm))
        white = &p;
    const vision::PointMm w = white->rect.centre();
    const vision::RectMm whiteArea{w.xMm - 3, w.yMm - 8, w.xMm + 3, w.yMm + 8};
    const auto ratioError = [&](const CodeTable& codes) {
      const RegionLight a = regionLight(metered, setup.scene->light(), rig.model, window, codes);
      const RegionLight b = regionLight(metered, setup.scene->light(), rig.model, whiteArea, codes);
      double worst = 0.0;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs((a.decoded[c] / b.decoded[c]) /
                                             (a.truth[c] / b.truth[c]) -
                                         1.0));
      return worst;
    };
    const double floor = ratioError(CodeTable(truth));  // noise and quantisation
    const double measured = ratioError(CodeTable(fit.curve));
    const double srgb = ratioError(CodeTable::srgb());
    std::printf("[ %s ] %s\n[ %s ] curve error over linear %.4f..%.3f: %.2f %% relative to the "
                "white, %.2f %% as scaled (decode(1) = 1); window / white ratio error: true curve "
                "%.2f %%, measured %.2f %%, sRGB %.2f %%\n",
                truth.name().c_str(), fit.summary().c_str(), truth.name().c_str(), lo, hi,
                100 * curveError, 100 * scaledError, 100 * floor, 100 * measured, 100 * srgb);
    // The ratio reads the curve at two levels: at most the curve's error at each, plus the floor.
    EXPECT_LT(measured, 2 * curveError + floor);
    if (truth.name() == "imx708-tuning") {
      EXPECT_GT(srgb, 3 * measured) << "sRGB decoding should be visibly wrong on this camera";
    }
  }
}

TEST(ResponseCurve, FramesWithoutTheTargetAreAnErrorNamingTheCamera) {
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  std::vector<hal::Frame> blank;
  for (int i = 0; i < 6; ++i) {
    hal::Frame frame;
    frame.image.width = camera.intrinsics.widthPx;
    frame.image.height = camera.intrinsics.heightPx;
    frame.image.channels = 3;
    frame.image.bitDepth = 8;
    frame.image.samples.assign(std::size_t(frame.image.width) * frame.image.height * 3, 128);
    frame.metadata.sequence = 10 + i;
    frame.metadata.exposureUs = 1000.0 * (1 << i);
    blank.push_back(frame);
  }
  ResponseFitParams params;
  params.cameraName = "uvc:/dev/video0";
  try {
    fitResponse(blank, vision::defaultTarget(), camera, params);
    FAIL() << "no error";
  } catch (const ResponseFitError& error) {
    EXPECT_NE(std::string(error.what()).find("uvc:/dev/video0, 6 bracket frames (sequence 10..15)"
                                             ": the target was not found"),
              std::string::npos)
        << error.what();
  }
  blank[2].metadata.exposureUs = 0.0;  // a UVC camera that does not say its exposure
  EXPECT_THROW(fitResponse(blank, vision::defaultTarget(), camera, params), ResponseFitError);
  blank.resize(3);
  EXPECT_THROW(fitResponse(blank, vision::defaultTarget(), camera, params), ResponseFitError);
}

}  // namespace
}  // namespace slicecap::capture
