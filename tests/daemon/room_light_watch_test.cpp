// RoomLightWatch: the status's warnings of a bright room light and of a flicker the frame
// duration does not hide, from the latest samples' figures.
#include "slicecap/daemon/room_light_watch.hpp"

#include <gtest/gtest.h>

namespace slicecap::daemon {
namespace {

capture::FrameOutcome::Measurement measured(double roomToLed, std::optional<double> change) {
  capture::FrameOutcome::Measurement m;
  m.roomToLed = roomToLed;
  m.roomChangeToLed = change;
  return m;
}

TEST(RoomLightWatch, WarnsOfABrightRoomAndOfAFlickerTheFramesDoNotHide) {
  RoomLightWatch watch;
  EXPECT_TRUE(watch.warnings().empty());
  EXPECT_TRUE(watch.summary().empty()) << "nothing before the first sample";
  for (int i = 0; i < 10; ++i) watch.note(measured(0.1, 0.004));
  EXPECT_TRUE(watch.warnings().empty()) << "10 % of the LED, steady: nothing to say";
  EXPECT_NEAR(*watch.roomToLed(), 0.1, 1e-12);
  EXPECT_NEAR(watch.summary()["change_to_led"].get<double>(), 0.004, 1e-12);

  // The room brightens to 40 % of the LED and its lamp flickers unhidden: the latest 32 count.
  for (int i = 0; i < 32; ++i) watch.note(measured(0.4, i % 2 ? 0.06 : -0.06));
  const std::vector<std::string> warnings = watch.warnings();
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("40.0 % of the LED's light"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("dim the room"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("changes by 6.0 %"), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[1].find("set mains_hz"), std::string::npos) << warnings[1];

  watch.reset();
  EXPECT_TRUE(watch.warnings().empty()) << "a new sweep run starts afresh";
  watch.note(measured(0.1, std::nullopt));  // one-sided: no change figure
  EXPECT_FALSE(watch.roomChangeToLed());
}

}  // namespace
}  // namespace slicecap::daemon
