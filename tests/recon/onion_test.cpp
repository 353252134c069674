// The onion map: its inverse, the highlight alignment of the view-relative light, no seam.
#include "slicecap/recon/onion.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "slicecap/core/angles.hpp"

namespace slicecap::recon {
namespace {

TEST(Onion, InverseGivesBackTheUnitVector) {
  for (double theta = 0.0; theta < 89.0; theta += 7.0) {
    for (double phi = 0.0; phi < 360.0; phi += 13.0) {
      const OnionAngles o = onionAngles({theta, phi});
      const UnitVector u = toUnitVector({theta, phi});
      EXPECT_NEAR(std::sin(o.bRad), u.x, 1e-12);
      EXPECT_NEAR(std::sin(o.aRad) * std::cos(o.bRad), u.y, 1e-12);
      EXPECT_NEAR(std::cos(o.aRad) * std::cos(o.bRad), u.z, 1e-12);
    }
  }
}

TEST(Onion, ViewRelativeLightAlignsTheSpecularAndRetroDirections) {
  for (double thetaV : {15.0, 30.0, 75.0}) {
    for (double phiV : {0.0, 40.0, 300.0}) {
      const OnionAngles specular = onionAnglesRelativeToView({thetaV, phiV + 180.0}, phiV);
      EXPECT_NEAR(specular.aRad, degToRad(thetaV), 1e-12);
      EXPECT_NEAR(specular.bRad, 0.0, 1e-12);
      const OnionAngles retro = onionAnglesRelativeToView({thetaV, phiV}, phiV);
      EXPECT_NEAR(retro.aRad, -degToRad(thetaV), 1e-12);
      EXPECT_NEAR(retro.bRad, 0.0, 1e-12);
    }
  }
}

TEST(Onion, HasNoSeamAtAzimuthZero) {
  const FeaturePoint a = onionFeatures({45, 359.99}, {60, 0.01});
  const FeaturePoint b = onionFeatures({45, 0.01}, {60, 359.99});
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_NEAR(a[k], b[k], 1e-3) << k;
}

TEST(Onion, AbsoluteFrameUsesThePlainMapForTheLight) {
  const FeaturePoint f = onionFeatures({30, 100}, {75, 20}, OnionFrame::Absolute);
  const OnionAngles light = onionAngles({30, 100});
  EXPECT_DOUBLE_EQ(f[0], light.aRad);
  EXPECT_DOUBLE_EQ(f[1], light.bRad);
}

}  // namespace
}  // namespace slicecap::recon
