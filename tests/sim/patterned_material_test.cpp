// The virtual rig's woven material as a camera's pixels read it: each pixel the area mean of the
// weave over its footprint on the target, not the thread at its centre.
#include "slicecap/sim/patterned_material.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::sim {
namespace {

constexpr int kSteps = 400;

// The share of warp over a box by brute force: the point weights on a fine grid, independently
// of the pattern's own box formula.
double boxMeanByPoints(const PatternedMaterial& m, double x, double y, double hx, double hy) {
  double sum = 0.0;
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j)
      sum += m.firstWeightAt(x - hx + (i + 0.5) * 2 * hx / kSteps,
                             y - hy + (j + 0.5) * 2 * hy / kSteps);
  return sum / (kSteps * kSteps);
}

TEST(WovenPattern, ABoxReadsTheShareOfWarpItCovers) {
  const auto woven = makeWovenMaterial(2.5);
  // A point is its thread, on either side of the origin.
  for (double x : {-6.2, -1.0, 0.4, 3.1, 7.7})
    for (double y : {-3.3, -0.2, 1.2, 5.6})
      EXPECT_EQ(woven->firstWeightOver(x, y, 0.0, 0.0), woven->firstWeightAt(x, y))
          << x << ", " << y;
  // Inside one square: all of it; a whole period each way: half.
  EXPECT_DOUBLE_EQ(woven->firstWeightOver(1.25, 1.25, 1.0, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(woven->firstWeightOver(3.75, 1.25, 1.0, 1.0), 0.0);
  EXPECT_NEAR(woven->firstWeightOver(0.7, -3.1, 2.5, 2.5), 0.5, 1e-12);
  // Any box, against the points: boxes of a pixel's footprint at 300 mm, up to a grazing view's.
  std::mt19937 random(3);
  std::uniform_real_distribution<double> place(-20.0, 20.0), half(0.05, 4.0);
  // The grid's error: each stripe edge inside the box misplaces at most half a step's share
  // of its axis.
  const auto edgesIn = [](double centre, double halfWidth) {
    return std::floor((centre + halfWidth) / 2.5) - std::floor((centre - halfWidth) / 2.5);
  };
  for (int n = 0; n < 40; ++n) {
    const double x = place(random), y = place(random), hx = half(random), hy = half(random);
    EXPECT_NEAR(woven->firstWeightOver(x, y, hx, hy), boxMeanByPoints(*woven, x, y, hx, hy),
                (edgesIn(x, hx) + edgesIn(y, hy)) / (2.0 * kSteps) + 1e-9)
        << "box at " << x << ", " << y << " half-widths " << hx << ", " << hy;
  }
}

TEST(WovenPattern, ThreadsFinerThanAPixelAreHalfEachEverywhere) {
  const auto fine = makeWovenMaterial(2.5, true);
  for (double x : {-6.2, 0.4, 3.1})
    EXPECT_EQ(fine->firstWeightAt(x, 1.0), 0.5);
  EXPECT_EQ(fine->firstWeightOver(1.25, 1.25, 1.0, 1.0), 0.5);
  EXPECT_NE(loadMaterial("woven:fine=1")->describe().find("finer than a pixel"), std::string::npos);
  EXPECT_THROW(loadMaterial("woven:fine=0.5"), MaterialError);
}

// One LED-on frame of `material` seen from 75 deg off the normal (the window foreshortened 4 x,
// a pixel ~1 mm deep on the target at 300 mm), linear, without noise.
std::vector<float> grazingFrame(const std::string& material, const vision::CameraModel& camera) {
  RigParams rig = RigParams::ideal();
  rig.readNoise = 0.0;
  rig.fullWellElectrons = 0.0;
  const FrameRenderer renderer(camera, vision::defaultTarget(), loadMaterial(material), rig);
  const double theta = 75.0 * std::numbers::pi / 180.0;
  FrameScene scene;
  scene.exposurePoses = {vision::lookAtPose({300.0 * std::sin(theta), 0.0, 300.0 * std::cos(theta)},
                                            {0, 0, 0}, {0, 0, 1})};
  scene.lightMm = {-300.0 * std::sin(theta) * std::cos(0.3),
                   300.0 * std::sin(theta) * std::sin(0.3), 300.0 * std::cos(theta)};
  return renderer.renderLinear(scene);
}

TEST(WovenPattern, AGrazingViewOfAFineWeaveReadsItsMixNotAliasedThreads) {
  // A 1 mm weave at 75 deg: each pixel spans ~1.2 mm of the target along the view, ~0.3 mm
  // across. The pixels near the window centre, in blocks of 4 x 4 (~4.7 x 1.2 mm), against the
  // same frame of the threads mixed at every point. Such a box holds 0.5 +- 0.05 of warp (its
  // stripes' shares 0.5 +- 0.08 along and +- 0.32 across, the product's deviation twice theirs),
  // ~7 % in blue, where the threads differ most (diffuse 0.32 against 0.05): measured 8.0 %.
  // Point-sampled, a block's rows fell on one thread or the other as the beat of the pixel rows
  // and the squares went: 33.8 % (the renderer before it integrated the footprint). Not under
  // 2 % either: the blocks do differ by their share of warp, which a pattern lost or a footprint
  // many pixels wide would smooth away.
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  const std::vector<float> weave = grazingFrame("woven:cell=1", camera);
  const std::vector<float> mixed = grazingFrame("woven:cell=1,fine=1", camera);
  const int width = camera.intrinsics.widthPx;
  const Eigen::Vector2d centre = camera.pixelOf({0.0, 0.0});
  double worst = 0.0;
  int blocks = 0;
  for (int by = -12; by < 12; by += 4)
    for (int bx = -40; bx < 40; bx += 4) {
      double sumWeave[3] = {}, sumMixed[3] = {};
      for (int dy = 0; dy < 4; ++dy)
        for (int dx = 0; dx < 4; ++dx) {
          const std::size_t i = 3 * (std::size_t(int(centre.y()) + by + dy) * width +
                                     std::size_t(int(centre.x()) + bx + dx));
          for (int c = 0; c < 3; ++c)
            sumWeave[c] += weave[i + c], sumMixed[c] += mixed[i + c];
        }
      for (int c = 0; c < 3; ++c) {
        ASSERT_GT(sumMixed[c], 0.0);
        worst = std::max(worst, std::abs(sumWeave[c] / sumMixed[c] - 1.0));
      }
      ++blocks;
    }
  EXPECT_EQ(blocks, 120);
  std::cout << "worst 4 x 4 block against the mixed threads: " << 100 * worst << " %\n";
  EXPECT_LT(worst, 0.12) << "the worst 4 x 4 block's channel against the mixed threads'";
  EXPECT_GT(worst, 0.02) << "no block shows its share of warp";
}

}  // namespace
}  // namespace slicecap::sim
