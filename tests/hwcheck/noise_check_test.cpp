// fitSensorNoise: read and shot noise from (level, variance) points, and the fits it refuses.
#include "slicecap/hwcheck/noise_check.hpp"

#include <gtest/gtest.h>

namespace slicecap::hwcheck {
namespace {

NoisePoint at(double level, const capture::SensorNoise& noise, double gain = 1.0) {
  NoisePoint p;
  p.level = level;
  p.gain = gain;
  p.variance = noise.pixelVariance(level, gain);
  p.pixels = 5000;
  return p;
}

TEST(FitSensorNoise, RecoversReadAndShotNoiseFromThreeLevels) {
  const capture::SensorNoise truth{0.003, 5000.0};
  const NoiseResult fit = fitSensorNoise({at(0.3, truth), at(0.075, truth), at(0.019, truth)});
  ASSERT_TRUE(fit.noise) << fit.problem;
  EXPECT_NEAR(fit.noise->readNoise, 0.003, 1e-6);
  EXPECT_NEAR(fit.noise->fullWellElectrons, 5000.0, 1e-3);
}

TEST(FitSensorNoise, TheGainIsTakenOut) {
  // At gain 4, a full-scale value stands for a quarter of the electrons: 4 x the shot variance.
  const capture::SensorNoise truth{0.002, 8000.0};
  const NoiseResult fit = fitSensorNoise({at(0.3, truth, 4.0), at(0.05, truth, 4.0)});
  ASSERT_TRUE(fit.noise) << fit.problem;
  EXPECT_NEAR(fit.noise->fullWellElectrons, 8000.0, 1e-3);
}

TEST(FitSensorNoise, RefusesLevelsTooCloseOrTooFewPixelsOrNoiseThatDoesNotGrow) {
  const capture::SensorNoise truth{0.002, 8000.0};
  EXPECT_NE(fitSensorNoise({at(0.3, truth), at(0.2, truth)}).problem.find("too close"), std::string::npos);
  NoisePoint few = at(0.05, truth);
  few.pixels = 10;
  EXPECT_NE(fitSensorNoise({at(0.3, truth), few}).problem.find("fewer than two"), std::string::npos);
  NoisePoint bright = at(0.3, truth), dark = at(0.03, truth);
  bright.variance = dark.variance / 2;  // a denoising ISP that smooths bright areas harder
  const NoiseResult denoised = fitSensorNoise({bright, dark});
  EXPECT_FALSE(denoised.noise);
  EXPECT_NE(denoised.problem.find("does not grow"), std::string::npos) << denoised.problem;
  EXPECT_EQ(sensorNoiseItem(denoised, "cam").verdict, Verdict::Warn);
}

}  // namespace
}  // namespace slicecap::hwcheck
