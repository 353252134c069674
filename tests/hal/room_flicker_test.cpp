// RoomFlicker: a lamp's light over an exposure window, and the frame duration that hides it.
#include "slicecap/hal/room_flicker.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace slicecap::hal {
namespace {

TEST(RoomFlicker, AWindowOfWholePeriodsSeesTheMeanAndAShortOneTheWaveform) {
  const RoomFlicker flicker{100.0, 0.3, 0.25};
  for (double startUs : {0.0, 1234.0, 5e9 + 777.0}) {
    EXPECT_NEAR(flicker.meanFactor(startUs, 10000.0), 1.0, 1e-9) << startUs;
    EXPECT_NEAR(flicker.meanFactor(startUs, 30000.0), 1.0, 1e-9) << startUs;
  }
  // Phase 0.25 cycles at t = 0: cos(pi / 2) = 0; a quarter period later, cos(pi) = -1.
  EXPECT_NEAR(flicker.factorAt(0.0), 1.0, 1e-9);
  EXPECT_NEAR(flicker.factorAt(2500.0), 0.7, 1e-9);
  EXPECT_NEAR(flicker.meanFactor(2500.0 - 0.5, 1.0), 0.7, 1e-6);
  // Half a period centred on the trough: the mean of cos over it is -2 / pi.
  EXPECT_NEAR(flicker.meanFactor(0.0, 5000.0), 1.0 - 0.3 * 2.0 / std::numbers::pi, 1e-9);
  // An exposure of a period and a half keeps a third of the half period's swing.
  EXPECT_NEAR(flicker.meanFactor(0.0, 15000.0), 1.0 - 0.3 * 2.0 / (3.0 * std::numbers::pi), 1e-9);
  EXPECT_EQ((RoomFlicker{0.0, 0.3, 0.0}).meanFactor(100.0, 50.0), 1.0) << "0 Hz: steady";
}

TEST(RoomFlicker, TheFrameDurationForTheMainsIsWholeFlickerPeriodsNearThirtyFramesASecond) {
  EXPECT_EQ(flickerHzOfMains(50), 100.0);
  EXPECT_EQ(flickerHzOfMains(60), 120.0);
  ASSERT_TRUE(frameDurationUsForMains(50));
  EXPECT_NEAR(*frameDurationUsForMains(50), 40000.0, 1e-6);  // 4 x 10 ms, 25 fps
  ASSERT_TRUE(frameDurationUsForMains(60));
  EXPECT_NEAR(*frameDurationUsForMains(60), 1e6 / 30.0, 1e-6);  // 4 x 8.33 ms, 30 fps
  EXPECT_FALSE(frameDurationUsForMains(0));
  // Every row of consecutive frames then starts at the same phase.
  for (int mains : {50, 60}) {
    const RoomFlicker flicker{flickerHzOfMains(mains), 0.5, 0.1};
    const double frameUs = *frameDurationUsForMains(mains);
    for (double rowUs : {0.0, 3333.0, 17000.0})
      EXPECT_NEAR(flicker.meanFactor(rowUs, 1000.0), flicker.meanFactor(rowUs + frameUs, 1000.0),
                  1e-9)
          << mains << " " << rowUs;
  }
}

TEST(RoomFlicker, RefusesValuesOutOfRangeNamingThem) {
  std::string why;
  EXPECT_TRUE((RoomFlicker{100.0, 0.1, 0.0}).isValid(&why));
  EXPECT_FALSE((RoomFlicker{0.5, 0.1, 0.0}).isValid(&why));
  EXPECT_NE(why.find("flicker frequency"), std::string::npos) << why;
  EXPECT_FALSE((RoomFlicker{100.0, 1.5, 0.0}).isValid(&why));
  EXPECT_NE(why.find("flicker depth"), std::string::npos) << why;
}

}  // namespace
}  // namespace slicecap::hal
