// LedStrobe against synthetic frames of a timed camera (no pixels, exact times): the label of a
// clean frame, where planned switches land, the line time assumed when the camera does not say
// it, and timestamps on another clock than the LED's.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>

#include "../support/plain_led.hpp"
#include "slicecap/capture/led_gate.hpp"
#include "slicecap/daemon/led_strobe.hpp"
#include "slicecap/hal/led_timeline.hpp"

namespace slicecap::daemon {
namespace {

constexpr int kWidth = 16, kHeight = 720;

// Frames as a timed camera delivers them, without pixels: row 0's exposure starts every
// `periodUs`, the timestamp is row 0's readout start (libcamera's SensorTimestamp) on a clock
// `stampAheadUs` ahead of the LED's, and each arrives on the LED's clock after its last row is read
// out plus the ISP's hand-off.
struct TimedFrames {
  std::int64_t periodUs = 33333;
  double exposureUs = 8000.0, lineTimeUs = 40.0, deliveryLatencyUs = 12000.0;
  bool reportsLineTime = true;
  std::int64_t firstStartUs = 10'000'000, stampAheadUs = 0;

  std::int64_t row0StartUs(std::uint64_t sequence) const {
    return firstStartUs + std::int64_t(sequence) * periodUs;
  }
  // When row `row` of frame `sequence` starts and ends its exposure, on the LED's clock.
  double rowStartUs(std::uint64_t sequence, int row) const {
    return double(row0StartUs(sequence)) + row * lineTimeUs;
  }
  double rowEndUs(std::uint64_t sequence, int row) const {
    return rowStartUs(sequence, row) + exposureUs;
  }
  std::int64_t arrivalUs(std::uint64_t sequence) const {
    return static_cast<std::int64_t>(rowStartUs(sequence, 0) + exposureUs + kHeight * lineTimeUs +
                                     deliveryLatencyUs);
  }
  hal::Frame frame(std::uint64_t sequence) const {
    hal::Frame frame;
    frame.image.width = kWidth;
    frame.image.height = kHeight;
    frame.image.channels = 3;
    frame.metadata.sequence = sequence;
    frame.metadata.exposureUs = exposureUs;
    frame.metadata.exposureStartUs = row0StartUs(sequence) + stampAheadUs;
    frame.metadata.timestampUs =
        row0StartUs(sequence) + static_cast<std::int64_t>(exposureUs) + stampAheadUs;
    if (reportsLineTime) frame.metadata.lineTimeUs = lineTimeUs;
    return frame;
  }
};

// The rows of interest of the synthetic-frame tests.
constexpr capture::RowSpan kRows{240, 480};

// A frame whose rows of interest saw the LED on throughout is labelled on, and off throughout,
// off: the capture sorts LED-on from room-light frames by this label.
TEST(LedStrobe, ACleanFrameIsLabelledWithTheStateItsRowsSaw) {
  const TimedFrames frames;
  auto commanded = std::make_shared<hal::LedTimeline>(true);
  test::PlainLed led;
  LedStrobe strobe({}, led, commanded, "cam");
  strobe.noteRows(kRows);
  hal::Frame first = frames.frame(0);
  strobe.label(first, frames.arrivalUs(0));
  // Off between frame 0's last row of interest and frame 1's first, guard clear of both.
  const double gapUs = frames.rowStartUs(1, kRows.first) - frames.rowEndUs(0, kRows.last);
  ASSERT_GT(gapUs, 4 * StrobeSettings{}.guardUs);
  commanded->record(static_cast<std::int64_t>(frames.rowEndUs(0, kRows.last) + gapUs / 2), false);
  hal::Frame second = frames.frame(1);
  strobe.label(second, frames.arrivalUs(1));

  ASSERT_EQ(strobe.stats().framesClean, 2u);
  ASSERT_EQ(strobe.stats().framesMixed, 0u);
  EXPECT_TRUE(first.metadata.ledOn) << "the LED shone on every row of interest";
  EXPECT_FALSE(second.metadata.ledOn) << "the LED was off over every row of interest";
}

// Frames one period apart, labelled; every switch planned from them (for any time over the next
// few frames) falls in the gap between frame j - 1's last row of interest and frame j's first,
// guard included. The gap (period - exposure - the rows' readout span) is a few percent of the
// period here, so an estimate of the period off by 10 % puts a switch a frame or more ahead into
// frame j's rows.
TEST(LedStrobe, PlannedSwitchesFallBetweenTheRowsOfInterestOfConsecutiveFrames) {
  TimedFrames frames;
  frames.exposureUs = 22000.0;
  const StrobeSettings settings;
  const double gapUs = frames.rowStartUs(1, kRows.first) - frames.rowEndUs(0, kRows.last);
  ASSERT_GT(gapUs, 2 * settings.guardUs);
  ASSERT_LT(gapUs, 0.1 * double(frames.periodUs)) << "a 10 % error must not fit in the gap";
  auto commanded = std::make_shared<hal::LedTimeline>(true);
  test::PlainLed led;
  LedStrobe strobe(settings, led, commanded, "cam");
  strobe.noteRows(kRows);
  constexpr std::uint64_t kLabelled = 4;
  for (std::uint64_t k = 0; k < kLabelled; ++k) {
    hal::Frame frame = frames.frame(k);
    strobe.label(frame, frames.arrivalUs(k));
  }
  std::set<std::uint64_t> planned;
  const std::int64_t fromUs = frames.arrivalUs(kLabelled - 1);
  for (std::int64_t earliestUs = fromUs; earliestUs < fromUs + 5 * frames.periodUs;
       earliestUs += frames.periodUs / 7) {
    const std::optional<PlannedSwitch> next = strobe.plan(earliestUs);
    ASSERT_TRUE(next) << earliestUs;
    const std::uint64_t j = next->forSequence;
    ASSERT_GE(j, kLabelled);
    planned.insert(j);
    EXPECT_GE(next->atUs, earliestUs);
    const auto afterUs = std::int64_t(frames.rowEndUs(j - 1, kRows.last) + settings.guardUs);
    const auto beforeUs = std::int64_t(frames.rowStartUs(j, kRows.first) - settings.guardUs);
    EXPECT_GE(next->atUs, afterUs)
        << "the switch for frame " << j << " lands in frame " << j - 1 << "'s rows";
    EXPECT_LE(next->atUs, beforeUs) << "the switch for frame " << j << " lands in its own rows";
    if (HasFailure()) break;  // one wrong switch says it; the rest repeat it
  }
  if (!HasFailure()) {
    EXPECT_GE(planned.size(), 2u) << "switches more than a frame ahead were planned too";
  }
}

// A camera that does not say its line time: the strobe takes the readout to span the measured
// frame period (no readout_us). A switch just after the rows of interest of a frame read out over
// exactly that span leaves the frame clean, on; a period overestimated by 10 % would stretch the
// rows' readout over the switch (a mixed frame).
TEST(LedStrobe, WithoutALineTimeTheRowsSpanTheMeasuredFramePeriod) {
  TimedFrames frames;
  frames.reportsLineTime = false;
  frames.lineTimeUs = double(frames.periodUs) / kHeight;
  auto commanded = std::make_shared<hal::LedTimeline>(true);
  test::PlainLed led;
  const StrobeSettings settings;
  LedStrobe strobe(settings, led, commanded, "cam");
  strobe.noteRows(kRows);
  constexpr std::uint64_t kLast = 3;  // frames 0..2 show the period
  const double switchUs = frames.rowEndUs(kLast, kRows.last) + settings.guardUs + 500.0;
  ASSERT_GT(0.1 * kRows.last * frames.lineTimeUs, settings.guardUs + 500.0)
      << "a 10 % longer line time must reach past the switch";
  for (std::uint64_t k = 0; k < kLast; ++k) {
    hal::Frame frame = frames.frame(k);
    strobe.label(frame, frames.arrivalUs(k));
  }
  commanded->record(static_cast<std::int64_t>(switchUs), false);
  hal::Frame frame = frames.frame(kLast);
  strobe.label(frame, frames.arrivalUs(kLast));
  ASSERT_TRUE(frame.metadata.ledExposure);
  EXPECT_NEAR(frame.metadata.ledExposure->lineTimeUs, frames.lineTimeUs, 1e-6);
  const hal::LedExposure::State state =
      frame.metadata.ledExposure->stateOver(kRows.first, kRows.last);
  EXPECT_EQ(std::string(hal::toString(state)), "on");
  EXPECT_EQ(strobe.stats().framesMixed, 0u);
}

// Timestamps on another clock than the LED's (0.5 s ahead of each frame's arrival) cannot place
// a frame against the LED's timeline: the strobe goes untimed and says so. Stamps within the
// allowed lead over the arrival (the two clocks read a little apart) keep it timed.
TEST(LedStrobe, TimestampsAheadOfTheArrivalBeyondTheLimitMakeTheStrobeUntimed) {
  for (const std::int64_t aheadUs : {std::int64_t(500'000), std::int64_t(0)}) {
    SCOPED_TRACE(aheadUs);
    TimedFrames frames;
    frames.stampAheadUs = aheadUs;
    test::PlainLed led;
    LedStrobe strobe({}, led, std::make_shared<hal::LedTimeline>(true), "cam0");
    for (std::uint64_t k = 0; k < 8; ++k) {
      hal::Frame frame = frames.frame(k);
      strobe.label(frame, frames.arrivalUs(k));
    }
    if (aheadUs > 0) {
      EXPECT_TRUE(strobe.untimed());
      EXPECT_NE(strobe.stats().warning.find("cam0 reports no usable frame timestamps"),
                std::string::npos)
          << strobe.stats().warning;
    } else {
      EXPECT_FALSE(strobe.untimed());
      EXPECT_TRUE(strobe.stats().warning.empty()) << strobe.stats().warning;
    }
  }
}

TEST(LedStrobe, TimestampsAFractionOfAMillisecondAfterTheArrivalKeepTheStrobeTimed) {
  TimedFrames frames;
  // The stamp 0.5 ms after the daemon's reading of its clock at the arrival.
  const std::int64_t stampAfterArrivalUs = 500;
  frames.stampAheadUs =
      frames.arrivalUs(0) - frames.frame(0).metadata.timestampUs + stampAfterArrivalUs;
  test::PlainLed led;
  LedStrobe strobe({}, led, std::make_shared<hal::LedTimeline>(true), "cam0");
  for (std::uint64_t k = 0; k < 8; ++k) {
    hal::Frame frame = frames.frame(k);
    strobe.label(frame, frames.arrivalUs(k));
    EXPECT_EQ(frame.metadata.timestampUs, frames.arrivalUs(k) + stampAfterArrivalUs);
  }
  EXPECT_FALSE(strobe.untimed());
}

}  // namespace
}  // namespace slicecap::daemon
