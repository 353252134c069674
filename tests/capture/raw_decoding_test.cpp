// End-to-end: linear light from the RAW stream on the model camera (sim -> hal -> capture): the
// virtual rig's target seen by a sensor offering SRGGB10_CSI2P (black level, shot and read noise,
// 10-bit codes), packed, decoded by hal::decodeBayer and read by the pipeline's LinearView. The
// window over the white reference beside it must come out as the scene's linear light says, where
// the same camera's processed frames read as sRGB do not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../support/bracket_rig.hpp"
#include "slicecap/capture/linear_view.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {
namespace {

struct StillRig {
  std::shared_ptr<const sim::FrameRenderer> renderer = std::make_shared<sim::FrameRenderer>(
      vision::defaultSimulatedCamera(), vision::defaultTarget(), sim::loadMaterial("matte-paint"),
      sim::RigParams::ideal());
  std::shared_ptr<test::StillScene> scene =
      std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
};

// Mean over a target rectangle (12 x 12 points at pixel centres) of the frame read through
// LinearView and of the scene's light before any ISP (the sensor's linear signal), per channel.
struct RegionLight {
  Rgb read, sensor;
};
RegionLight regionLight(const hal::Frame& frame, const hal::SceneLight& light,
                        const vision::RectMm& rect, const CodeTable& codes) {
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  const vision::Pose pose = test::stillPose();
  const LinearView view(frame, codes);
  RegionLight out;
  int n = 0;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i) {
      const double x = rect.xMinMm + (i + 0.5) * rect.widthMm() / 12;
      const double y = rect.yMinMm + (j + 0.5) * rect.heightMm() / 12;
      const auto px = camera.project(pose.toCamera({x, y, 0.0}));
      const int u = int(std::lround(px->x())), v = int(std::lround(px->y()));
      const std::size_t at = (std::size_t(v) * light.widthPx + u) * 3;
      bool clipped = false;
      for (int c = 0; c < 3; ++c) {
        out.sensor[c] += light.ledRate[at + c] + light.ambientRate[at + c];
        out.read[c] += view.linear(u, v, c, 2.0, &clipped);
      }
      ++n;
    }
  out.read *= 1.0 / n;
  out.sensor *= 1.0 / n;
  return out;
}

// The largest relative error over the channels of (window / white) read from the frame.
double windowOverWhiteError(const StillRig& setup, const hal::Frame& frame, const CodeTable& codes) {
  const vision::TargetGeometry& target = setup.renderer->target();
  const vision::PointMm centre = target.window.centre();
  const vision::RectMm window{centre.xMm - 8, centre.yMm - 8, centre.xMm + 8, centre.yMm + 8};
  const vision::Patch* white = nullptr;
  for (const vision::Patch& p : target.patches)
    if (p.kind == vision::PatchKind::White && (!white || p.rect.xMaxMm < white->rect.xMaxMm))
      white = &p;
  const vision::PointMm w = white->rect.centre();
  const vision::RectMm whiteArea{w.xMm - 3, w.yMm - 8, w.xMm + 3, w.yMm + 8};
  const RegionLight a = regionLight(frame, setup.scene->light(), window, codes);
  const RegionLight b = regionLight(frame, setup.scene->light(), whiteArea, codes);
  double worst = 0.0;
  for (int c = 0; c < 3; ++c)
    worst = std::max(worst,
                     std::abs((a.read[c] / b.read[c]) / (a.sensor[c] / b.sensor[c]) - 1.0));
  return worst;
}

TEST(RawDecoding, TheModelsRawStreamReadsTheWindowOverTheWhiteAsTheSceneIs) {
  const StillRig setup;
  hal::SensorModel model;  // the IMX708's tuning curve and colour gains on the processed stream
  model.rawFormat = hal::BayerFormat{hal::BayerOrder::Rggb, 10, hal::BayerPacking::Csi2Packed};
  test::BracketRig raw(setup.scene, model);
  const hal::Frame rawFrame = raw.take({{raw.meteredExposureUs(), 1.0}}).front();
  ASSERT_EQ(rawFrame.encoding, PixelEncoding::Linear16);
  ASSERT_EQ(rawFrame.image.width, setup.renderer->camera().intrinsics.widthPx);

  model.rawFormat.reset();  // the same camera's processed stream, read as sRGB
  test::BracketRig processed(setup.scene, model);
  const hal::Frame processedFrame = processed.take({{processed.meteredExposureUs(), 1.0}}).front();
  ASSERT_EQ(processedFrame.encoding, PixelEncoding::Srgb8);

  const double rawError = windowOverWhiteError(setup, rawFrame, CodeTable::srgb());
  const double srgbError = windowOverWhiteError(setup, processedFrame, CodeTable::srgb());
  std::printf("[ raw ] window / white ratio error: RAW SRGGB10_CSI2P decoded %.2f %%, processed "
              "IMX708-curve frames read as sRGB %.2f %%\n",
              100 * rawError, 100 * srgbError);
  // 10-bit codes (1/959 of full scale a code) and ~144-pixel means of shot and read noise.
  EXPECT_LT(rawError, 0.01);
  EXPECT_GT(srgbError, 5 * rawError);
}

}  // namespace
}  // namespace slicecap::capture
