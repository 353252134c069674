// Sweep plans: the slice geometry of each kind, and the imperfections a realistic sweep has.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "slicecap/core/angles.hpp"
#include "slicecap/sim/rig.hpp"
#include "slicecap/sim/sim_error.hpp"
#include "slicecap/sim/simulate.hpp"

namespace slicecap::sim {
namespace {

double azimuthDifferenceDeg(double aDeg, double bDeg) {
  return std::abs(std::remainder(aDeg - bDeg, 360.0));
}

TEST(RigPlan, HdrMeteringPutsThePaperAndTheHighlightAtEightyPercent) {
  RigParams rig = RigParams::ideal();  // full scale per 20 W/(m^2 sr) s
  rig.maxExposureLevels = 3;
  // Paper 1 W/(m^2 sr): 0.8 / 20 s = 40 ms; a highlight 100 x brighter: 0.4 ms, a third between.
  const std::vector<double> three = chooseHdrLevelsUs({100.0, 1.0}, rig);
  ASSERT_EQ(three.size(), 3u);
  EXPECT_NEAR(three[0], 40000.0, 1e-6);
  EXPECT_NEAR(three[1], 4000.0, 1e-6);
  EXPECT_NEAR(three[2], 400.0, 1e-6);
  rig.maxExposureLevels = 2;
  EXPECT_EQ(chooseHdrLevelsUs({100.0, 1.0}, rig), (std::vector<double>{40000.0, 400.0}));
  // The sample square's brightest point, off the centre, sets the short level when brighter.
  EXPECT_EQ(chooseHdrLevelsUs({100.0, 1.0, 200.0}, rig), (std::vector<double>{40000.0, 200.0}));
  // Within 16 x, two levels even when three are allowed; within 2 x, the brighter's one exposure.
  rig.maxExposureLevels = 3;
  EXPECT_EQ(chooseHdrLevelsUs({10.0, 1.0}, rig).size(), 2u);
  const std::vector<double> one = chooseHdrLevelsUs({1.5, 1.0}, rig);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(one[0], 0.8 / (20.0 * 1.5) * 1e6, 1e-6);
}

TEST(RigPlan, AnHdrBracketsLedPairsShareTheirNominalPosition) {
  const RigParams rig = RigParams::ideal();
  const auto camera = vision::defaultSimulatedCamera();
  const auto target = vision::defaultTarget();
  const SliceId slice{SliceKind::Diagonal, {30, 30}};
  const auto single = planSweep(slice, 15.0, rig, camera, target);
  const auto bracket = planSweep(slice, 15.0, rig, camera, target, 2);
  ASSERT_EQ(bracket.size(), 2 * single.size());
  for (std::size_t k = 0; k < bracket.size(); ++k) {
    // Frames 4q, 4q + 2 (LED on) at single frame 2q; 4q + 1, 4q + 3 (off) at 2q + 1.
    const std::size_t same = (k / 4) * 2 + k % 2;
    EXPECT_DOUBLE_EQ(bracket[k].sliceParameterDeg, single[same].sliceParameterDeg) << k;
    EXPECT_EQ(bracket[k].ledOn, single[same].ledOn) << k;
  }
  EXPECT_THROW(planSweep(slice, 15.0, rig, camera, target, 4), sim::SimError);
}

TEST(RigPlan, IdealSweepsFollowTheirSliceExactly) {
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  const vision::TargetGeometry target = vision::defaultTarget();
  for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
    const SliceId slice{kind, {75, 30}};
    const auto plans = planSweep(slice, 15.0, RigParams::ideal(), camera, target);
    ASSERT_EQ(plans.size(), 48u);
    for (const FramePlan& p : plans) {
      const Direction view = vision::directionFrom({0, 0, 0}, p.pose.cameraCentreMm());
      const Direction light = vision::directionFrom({0, 0, 0}, p.lightMm);
      EXPECT_NEAR(view.thetaDeg, 30.0, 1e-9);
      EXPECT_NEAR(light.thetaDeg, 75.0, 1e-9);
      EXPECT_NEAR(p.pose.cameraCentreMm().norm(), 300.0, 1e-9);
      EXPECT_NEAR(p.lightMm.norm(), 300.0, 1e-9);
      if (kind == SliceKind::Axial) {
        EXPECT_NEAR(azimuthDifferenceDeg(view.phiDeg, light.phiDeg + 15.0), 0.0, 1e-9);
        EXPECT_NEAR(azimuthDifferenceDeg(light.phiDeg, p.sliceParameterDeg), 0.0, 1e-9);
      } else {
        EXPECT_NEAR(azimuthDifferenceDeg(light.phiDeg, 360.0 - view.phiDeg), 0.0, 1e-9);
        EXPECT_NEAR(azimuthDifferenceDeg(view.phiDeg, p.sliceParameterDeg), 0.0, 1e-9);
      }
      // The window centre is in the middle of the image.
      const auto centre = camera.project(p.pose.toCamera({0, 0, 0}));
      ASSERT_TRUE(centre.has_value());
      EXPECT_NEAR(centre->x(), camera.intrinsics.cxPx, 1e-6);
      EXPECT_EQ(p.exposurePoses.size(), 1u);
      EXPECT_FALSE(p.occluder.has_value());
      EXPECT_FALSE(p.aimedOff);
      EXPECT_EQ(p.exposureScale, 1.0);
    }
  }
}

TEST(RigPlan, RealisticSweepsHaveEveryImperfectionAndStayNearTheSlice) {
  RigParams params = RigParams::realistic();
  params.framesPerSlice = 240;
  const auto plans = planSweep({SliceKind::Axial, {30, 75}}, 15.0, params,
                               vision::defaultSimulatedCamera(), vision::defaultTarget());
  int blurred = 0, occluded = 0, aimedOff = 0, dimmer = 0;
  double worstElevationDeg = 0.0;
  for (std::size_t k = 0; k < plans.size(); ++k) {
    const FramePlan& p = plans[k];
    blurred += p.exposurePoses.size() > 1;
    occluded += p.occluder.has_value();
    aimedOff += p.aimedOff;
    if (p.aimedOff) {
      // Some marker corner is out of the image, the window centre is in it.
      const vision::CameraModel camera = vision::defaultSimulatedCamera();
      bool cut = false;
      for (const vision::Marker& m : vision::defaultTarget().markers) {
        for (const vision::PointMm& c : m.cornersMm) {
          const auto px = camera.project(p.pose.toCamera({c.xMm, c.yMm, 0.0}));
          cut = cut || !px || px->x() < 0 || px->y() < 0 ||
                px->x() > camera.intrinsics.widthPx - 1 || px->y() > camera.intrinsics.heightPx - 1;
        }
      }
      EXPECT_TRUE(cut) << "frame " << k << " is aimed off with every marker in view";
      const auto centre = camera.project(p.pose.toCamera({0, 0, 0}));
      ASSERT_TRUE(centre.has_value());
      EXPECT_TRUE(centre->x() > 0 && centre->y() > 0 && centre->x() < camera.intrinsics.widthPx &&
                  centre->y() < camera.intrinsics.heightPx);
    }
    dimmer += p.exposureScale < 1.0;
    EXPECT_EQ(p.ledOn, k % 2 == 0);
    // An off frame shares its on frame's exposure (ambient subtraction needs the same one).
    if (!p.ledOn) {
      EXPECT_EQ(p.exposureScale, plans[k - 1].exposureScale);
    }
    const Direction view = vision::directionFrom({0, 0, 0}, p.pose.cameraCentreMm());
    worstElevationDeg = std::max(worstElevationDeg, std::abs(view.thetaDeg - 75.0));
  }
  EXPECT_GT(blurred, 10);
  EXPECT_GT(occluded, 3);
  EXPECT_GT(aimedOff, 3);
  EXPECT_GT(dimmer, 10);
  EXPECT_GT(worstElevationDeg, 1.0) << "no elevation jitter";
  EXPECT_LT(worstElevationDeg, 8.0) << "a hand-held capture stays within a few degrees";
}

TEST(RigPlan, PlansAreReproducibleAndBadParametersAreNamed) {
  const RigParams params = RigParams::realistic();
  const auto a = planSweep({SliceKind::Diagonal, {30, 30}}, 15.0, params,
                           vision::defaultSimulatedCamera(), vision::defaultTarget());
  const auto b = planSweep({SliceKind::Diagonal, {30, 30}}, 15.0, params,
                           vision::defaultSimulatedCamera(), vision::defaultTarget());
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_EQ(a[k].pose.translationMm, b[k].pose.translationMm);
  RigParams bad = params;
  bad.occlusionFraction = 1.5;
  std::string error;
  EXPECT_FALSE(bad.isValid(&error));
  EXPECT_NE(error.find("occlusion"), std::string::npos) << error;
  EXPECT_THROW(planSweep({SliceKind::Axial, {30, 30}}, 15.0, bad, vision::defaultSimulatedCamera(),
                         vision::defaultTarget()),
               sim::SimError);
}

}  // namespace
}  // namespace slicecap::sim
