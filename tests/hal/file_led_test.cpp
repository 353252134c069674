// The file LED logs every change with its time and ends off; its log's reader names a bad line.
#include "slicecap/hal/file_led.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "../support/test_support.hpp"
#include "slicecap/hal/clock.hpp"

namespace slicecap::hal {
namespace {

TEST(FileLed, LogsEveryChangeWithItsTimeAndEndsOff) {
  const auto log = test::freshTempDir() / "led.log";
  FakeClock clock(100);
  {
    FileLed led(log, clock);
    EXPECT_FALSE(led.isOn());
    clock.advanceUs(50);
    led.set(true);
    led.set(true);  // no change, no line
    clock.advanceUs(25);
    led.set(false);
    clock.advanceUs(25);
    led.set(true);
    clock.advanceUs(5);
  }
  const std::vector<LedEvent> expected = {
      {100, false}, {150, true}, {175, false}, {200, true}, {205, false}};
  EXPECT_EQ(readLedLog(log), expected);
}

TEST(FileLed, ReaderNamesTheBadLine) {
  const auto log = test::freshTempDir() / "led.log";
  std::ofstream(log) << "10 on\n20 dim\n";
  try {
    readLedLog(log);
    FAIL() << "a bad line was accepted";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("led.log:2"), std::string::npos) << e.what();
  }
}


}  // namespace
}  // namespace slicecap::hal
