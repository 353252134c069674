// The pinned frame duration's decisions (frame_timing.hpp): what the libcamera and V4L2 backends
// send for mains_hz, and how an exposure longer than the frame is handled.
#include "slicecap/hal/frame_timing.hpp"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <cmath>

#include "slicecap/hal/camera_error.hpp"
#include "slicecap/hal/room_flicker.hpp"

namespace slicecap::hal {
namespace {

TEST(PinnedFrameDuration, NothingIsSentWhenNoDurationIsPinned) {
  const FrameDurationPlan plan = planFrameDuration(std::nullopt, FrameDurationRange{10000, 1000000});
  EXPECT_FALSE(plan.limitsUs);
  EXPECT_FALSE(plan.grantedUs);
  EXPECT_TRUE(plan.notes.empty());
}

TEST(PinnedFrameDuration, APinnedDurationInsideTheModesRangeIsSentAsIs) {
  const std::optional<double> wanted = frameDurationUsForMains(50);
  ASSERT_TRUE(wanted);
  const FrameDurationPlan plan = planFrameDuration(wanted, FrameDurationRange{8333, 1200000});
  ASSERT_TRUE(plan.limitsUs);
  EXPECT_EQ(*plan.limitsUs, std::llround(*wanted));
  EXPECT_TRUE(plan.notes.empty());
}

TEST(PinnedFrameDuration, SixtyHertzIsRoundedToWholeMicroseconds) {
  const std::optional<double> wanted = frameDurationUsForMains(60);
  ASSERT_TRUE(wanted);
  const FrameDurationPlan plan = planFrameDuration(wanted, FrameDurationRange{8333, 1200000});
  ASSERT_TRUE(plan.limitsUs);
  EXPECT_LE(std::abs(double(*plan.limitsUs) - *wanted), 0.5);
}

TEST(PinnedFrameDuration, ADurationOutsideTheModesRangeIsClampedAndSaid) {
  // A sensor mode whose readout is longer than the wanted frame (e.g. a full-resolution mode).
  const FrameDurationPlan plan = planFrameDuration(40000.0, FrameDurationRange{66666, 1200000});
  ASSERT_TRUE(plan.limitsUs);
  EXPECT_EQ(*plan.limitsUs, 66666);
  ASSERT_TRUE(plan.grantedUs);
  EXPECT_DOUBLE_EQ(*plan.grantedUs, 66666.0);
  ASSERT_EQ(plan.notes.size(), 1u);
  EXPECT_NE(plan.notes[0].find("40000 us -> 66666 us"), std::string::npos) << plan.notes[0];
}

TEST(PinnedFrameDuration, ACameraWithoutTheControlGetsNothingAndItIsSaid) {
  const FrameDurationPlan plan = planFrameDuration(40000.0, std::nullopt);
  EXPECT_FALSE(plan.limitsUs);
  EXPECT_FALSE(plan.grantedUs);
  ASSERT_EQ(plan.notes.size(), 1u);
  EXPECT_NE(plan.notes[0].find("FrameDurationLimits"), std::string::npos) << plan.notes[0];
}

TEST(PinnedFrameDuration, AnExposureLongerThanThePinnedFrameIsClampedAndSaid) {
  const ExposureInFrame longer = clampExposureToFrame(50000.0, 40000.0);
  EXPECT_DOUBLE_EQ(longer.exposureUs, 40000.0);
  ASSERT_TRUE(longer.note);
  EXPECT_NE(longer.note->find("50000 us -> 40000 us"), std::string::npos) << *longer.note;

  const ExposureInFrame inside = clampExposureToFrame(12000.0, 40000.0);
  EXPECT_DOUBLE_EQ(inside.exposureUs, 12000.0);
  EXPECT_FALSE(inside.note);
  const ExposureInFrame unpinned = clampExposureToFrame(90000.0, std::nullopt);
  EXPECT_DOUBLE_EQ(unpinned.exposureUs, 90000.0);
  EXPECT_FALSE(unpinned.note);
}

TEST(PinnedFrameDuration, TheV4l2FrameIntervalIsTheDurationAsAReducedFraction) {
  const TimePerFrame fifty = timePerFrameOf(40000.0);
  EXPECT_EQ(fifty.numerator, 1u);
  EXPECT_EQ(fifty.denominator, 25u);
  const TimePerFrame sixty = timePerFrameOf(*frameDurationUsForMains(60));
  const std::optional<double> back = frameDurationUsOf(sixty);
  ASSERT_TRUE(back);
  EXPECT_NEAR(*back, *frameDurationUsForMains(60), 0.5);
  EXPECT_FALSE(frameDurationUsOf(TimePerFrame{0, 30}));
  EXPECT_FALSE(frameDurationUsOf(TimePerFrame{1, 0}));
  EXPECT_THROW(timePerFrameOf(0.0), CameraError);
}

TEST(PinnedFrameDuration, ThePowerLineMenuValuesAreVideodevs) {
  EXPECT_EQ(powerLineFrequencyMenuValue(0), V4L2_CID_POWER_LINE_FREQUENCY_DISABLED);
  EXPECT_EQ(powerLineFrequencyMenuValue(50), V4L2_CID_POWER_LINE_FREQUENCY_50HZ);
  EXPECT_EQ(powerLineFrequencyMenuValue(60), V4L2_CID_POWER_LINE_FREQUENCY_60HZ);
  EXPECT_THROW(powerLineFrequencyMenuValue(55), CameraError);
}

}  // namespace
}  // namespace slicecap::hal
