// LedTimeline, TimelineLed and LedExposure: on-time sums, row classification with the guard.
#include "slicecap/hal/led_timeline.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/hal_error.hpp"

namespace slicecap::hal {
namespace {

class CountingLed final : public Led {
 public:
  std::string id() const override { return "counting"; }
  void set(bool on) override {
    if (failNext) throw std::runtime_error("gpio failed");
    on_ = on;
  }
  bool isOn() const override { return on_; }
  bool failNext = false;

 private:
  bool on_ = false;
};

TEST(LedTimeline, SumsOnTimeOverAnyInterval) {
  LedTimeline timeline;
  timeline.record(100, true);
  timeline.record(300, false);
  timeline.record(500, true);
  EXPECT_DOUBLE_EQ(timeline.onTimeUs(0, 100), 0.0);
  EXPECT_DOUBLE_EQ(timeline.onTimeUs(0, 1000), 200.0 + 500.0);
  EXPECT_DOUBLE_EQ(timeline.onTimeUs(250, 550), 50.0 + 50.0);
  EXPECT_TRUE(timeline.stateAt(100));
  EXPECT_FALSE(timeline.stateAt(99));
  EXPECT_FALSE(timeline.stateAt(300));
}

TEST(LedTimeline, KeepsOnlyRealChangesAndRefusesGoingBack) {
  LedTimeline timeline;
  timeline.record(10, false);  // already off
  timeline.record(20, true);
  timeline.record(30, true);
  EXPECT_EQ(timeline.size(), 1u);
  EXPECT_THROW(timeline.record(5, false), hal::HalError);
}

TEST(LedTimeline, ForgettingTheOldKeepsTheStateAfterIt) {
  LedTimeline timeline;
  timeline.record(100, true);
  timeline.record(200, false);
  timeline.record(300, true);
  timeline.forgetBefore(250);
  EXPECT_EQ(timeline.size(), 1u);
  EXPECT_FALSE(timeline.stateAt(260));
  EXPECT_TRUE(timeline.stateAt(310));
  EXPECT_DOUBLE_EQ(timeline.onTimeUs(250, 400), 100.0);
}

TEST(LedExposure, ClassifiesRowsOfARollingShutterFrame) {
  LedTimeline timeline;
  timeline.record(0, true);
  // Rows start 10 us apart, each exposed 100 us: row r spans [1000 + 10 r, 1100 + 10 r).
  timeline.record(1500, false);
  const LedExposure exposure = timeline.exposureOf(1000, 10.0, 100.0, 100, 0.0);
  EXPECT_EQ(exposure.stateOver(0, 39), LedExposure::State::On);      // rows end by 1490
  EXPECT_EQ(exposure.stateOver(0, 40), LedExposure::State::On);      // row 40 ends at 1500
  EXPECT_EQ(exposure.stateOver(35, 45), LedExposure::State::Mixed);  // row 41 spans the switch
  EXPECT_EQ(exposure.stateOver(50, 99), LedExposure::State::Off);    // rows start at 1500 on
  EXPECT_DOUBLE_EQ(exposure.onFraction(45), 0.5);                    // [1450, 1550)
  EXPECT_DOUBLE_EQ(exposure.onFraction(10), 1.0);
  EXPECT_DOUBLE_EQ(exposure.onFraction(60), 0.0);
}

TEST(LedExposure, TheGuardWidensASwitchBothWays) {
  LedTimeline timeline;
  timeline.record(1500, true);
  const LedExposure exposure = timeline.exposureOf(1000, 10.0, 100.0, 100, 30.0);
  EXPECT_EQ(exposure.stateOver(0, 36), LedExposure::State::Off);    // row 36 ends at 1460
  EXPECT_EQ(exposure.stateOver(0, 38), LedExposure::State::Mixed);  // ends at 1480, guard 1470
  EXPECT_EQ(exposure.stateOver(54, 99), LedExposure::State::On);    // starts at 1540
  EXPECT_EQ(exposure.stateOver(52, 99), LedExposure::State::Mixed);  // 1520 is within the guard
}

TEST(TimelineLed, RecordsWhatTheLedDidAtTheClocksTimePlusItsDelay) {
  FakeClock clock(5000);
  auto timeline = std::make_shared<LedTimeline>();
  auto inner = std::make_unique<CountingLed>();
  CountingLed* raw = inner.get();
  TimelineLed led(std::move(inner), clock, timeline, 40);
  led.set(true);
  clock.advanceUs(1000);
  raw->failNext = true;
  EXPECT_THROW(led.set(false), std::runtime_error);
  EXPECT_TRUE(timeline->stateAt(7000));  // the refused switch is not on the timeline
  EXPECT_FALSE(timeline->stateAt(5039));
  EXPECT_TRUE(timeline->stateAt(5040));
  EXPECT_TRUE(led.isOn());
}

}  // namespace
}  // namespace slicecap::hal
