// measureFrameTiming: period, jitter and drops from timestamps and sequence numbers.
#include "slicecap/hwcheck/frame_timing.hpp"

#include <gtest/gtest.h>

namespace slicecap::hwcheck {
namespace {

SeenFrame at(std::uint64_t sequence, std::int64_t timestampUs, std::int64_t arrivalUs) {
  SeenFrame seen;
  seen.frame.metadata.sequence = sequence;
  seen.frame.metadata.timestampUs = timestampUs;
  seen.arrivalUs = arrivalUs;
  return seen;
}

TEST(FrameTiming, MeasuresPeriodJitterAndSequenceGaps) {
  std::vector<SeenFrame> frames;
  const std::int64_t jitter[] = {0, 100, 0, -100, 0, 0, 100, 0};
  std::uint64_t sequence = 0;
  for (int i = 0; i < 8; ++i, ++sequence) {
    if (i == 5) sequence += 2;  // two frames lost
    const std::int64_t t = 1'000'000 + std::int64_t(sequence) * 33'333 + jitter[i];
    frames.push_back(at(sequence, t, t + 40'000 + (i == 3 ? 9'000 : 0)));
  }
  const FrameTiming timing = measureFrameTiming(frames);
  ASSERT_TRUE(timing.hasTimestamps);
  EXPECT_NEAR(timing.periodUs, 33'333.0, 1.0);
  EXPECT_EQ(timing.dropped, 2);
  EXPECT_GT(timing.jitterUs, 50.0);  // steps of +-100 us about the period
  EXPECT_LT(timing.jitterUs, 150.0);
  EXPECT_DOUBLE_EQ(timing.timestampToArrivalUs, 40'000.0) << "the least: a late loop only adds";
  EXPECT_EQ(frameTimingItem(timing, "cam").verdict, Verdict::Warn) << "2 of 10 frames dropped";
}

TEST(FrameTiming, WithoutTimestampsFailsNamingTheCamera) {
  std::vector<SeenFrame> frames;
  for (std::uint64_t i = 0; i < 5; ++i) frames.push_back(at(i, 0, 1000 * std::int64_t(i)));
  const FrameTiming timing = measureFrameTiming(frames);
  EXPECT_FALSE(timing.hasTimestamps);
  const CheckItem item = frameTimingItem(timing, "/dev/video7");
  EXPECT_EQ(item.verdict, Verdict::Fail);
  EXPECT_NE(item.finding.find("/dev/video7"), std::string::npos);
  EXPECT_FALSE(measureFrameTiming({at(0, 5, 6)}).hasTimestamps) << "one frame says nothing";
}

}  // namespace
}  // namespace slicecap::hwcheck
