// fitLedTiming: the line time and the LED's offset from switches seen at their half-lit rows.
#include "slicecap/hwcheck/led_timing.hpp"

#include <gtest/gtest.h>

namespace slicecap::hwcheck {
namespace {

TEST(LedTiming, FitsLineTimeAndOffsetFromTheHalfLitRows) {
  LedTiming timing;
  timing.switchesMade = 6;
  // A 30 us line, the light 250 us after the record: switch - row0 mid = 30 x row - 250.
  const double rows[] = {300, 340, 380, 420, 460};
  for (double row : rows) timing.transitions.push_back({0.0, row, 30.0 * row - 250.0, 0});
  timing.transitions.push_back({0.0, 400.0, 30.0 * 400.0 - 250.0, 1});
  fitLedTiming(timing, 720);
  ASSERT_TRUE(timing.lineTimeUs) << timing.problem;
  EXPECT_NEAR(*timing.lineTimeUs, 30.0, 1e-9);
  EXPECT_NEAR(*timing.readoutUs, 30.0 * 720, 1e-6);
  EXPECT_NEAR(*timing.offsetUs, 250.0, 1e-6);
  EXPECT_NEAR(*timing.residualUs, 0.0, 1e-6);
  EXPECT_EQ(*timing.frameShift, 0);
  EXPECT_EQ(ledTimingItem(timing, "cam").verdict, Verdict::Ok);
}

TEST(LedTiming, TooFewOrBunchedSwitchesAreAProblemNotAFigure) {
  LedTiming few;
  few.switchesMade = 32;
  few.transitions = {{0, 300, 100, 0}, {0, 350, 200, 0}};
  fitLedTiming(few, 720);
  EXPECT_FALSE(few.lineTimeUs);
  EXPECT_NE(few.problem.find("only 2 of 32"), std::string::npos) << few.problem;
  EXPECT_EQ(ledTimingItem(few, "cam").verdict, Verdict::Fail);

  LedTiming bunched;
  bunched.transitions = {{0, 300, 100, 0}, {0, 305, 200, 0}, {0, 310, 300, 0}};
  fitLedTiming(bunched, 720);
  EXPECT_FALSE(bunched.lineTimeUs);
  EXPECT_NE(bunched.problem.find("span only 10 rows"), std::string::npos) << bunched.problem;
}

}  // namespace
}  // namespace slicecap::hwcheck
