// RoomLightWatch: the status's warnings of a bright room light and of a flicker the frame
// duration does not hide, from the latest samples' figures.
#include "slicecap/daemon/room_light_watch.hpp"

#include <gtest/gtest.h>

namespace slicecap::daemon {
namespace {

// A sample with its room-to-LED ratio, then an LED-off frame with its change from the one before.
void noteBoth(RoomLightWatch& watch, double roomToLed, std::optional<double> change) {
  capture::FrameOutcome sample;
  sample.kind = capture::FrameOutcome::Kind::Sample;
  sample.measurement.roomToLed = roomToLed;
  watch.note(sample);
  capture::FrameOutcome off;
  off.kind = capture::FrameOutcome::Kind::Ambient;
  off.measurement.roomChange = change;
  watch.note(off);
}

TEST(RoomLightWatch, WarnsOfABrightRoomAndOfAFlickerTheFramesDoNotHide) {
  RoomLightWatch watch;
  EXPECT_TRUE(watch.warnings().empty());
  EXPECT_FALSE(watch.view().toLed || watch.view().change || watch.view().changeToLed)
      << "nothing before the first sample";
  for (int i = 0; i < 10; ++i) noteBoth(watch, 0.1, 0.04);
  EXPECT_TRUE(watch.warnings().empty()) << "10 % of the LED, moving 4 % of itself: 0.4 % of the LED";
  EXPECT_NEAR(*watch.roomToLed(), 0.1, 1e-12);
  EXPECT_NEAR(watch.view().changeToLed.value_or(0.0), 0.004, 1e-12);

  // The room brightens to 40 % of the LED and its lamp flickers unhidden (15 % from frame to
  // frame: 6 % of the LED): the latest 32 count.
  for (int i = 0; i < 32; ++i) noteBoth(watch, 0.4, i == 5 ? 0.9 : 0.15);  // one outlier
  const std::vector<std::string> warnings = watch.warnings();
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("40.0 % of the LED's light"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("dim the room"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("changes by 6.0 %"), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[1].find("set mains_hz"), std::string::npos) << warnings[1];

  watch.reset();
  EXPECT_TRUE(watch.warnings().empty()) << "a new sweep run starts afresh";
  noteBoth(watch, 0.1, std::nullopt);  // no two consecutive LED-off frames: no change figure
  EXPECT_FALSE(watch.roomChangeToLed());
}

}  // namespace
}  // namespace slicecap::daemon
