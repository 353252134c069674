// GpiodLed's line lookup and its errors. No GPIO chip exists on a build machine, and on a box the
// names below exist nowhere, so every case here is an error path that must name chip and line.
#include "slicecap/hal/gpiod_led.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace slicecap::hal {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string errorOf(const GpioLineSpec& spec) {
  try {
    GpiodLed led(spec);
  } catch (const GpioError& error) {
    return error.what();
  }
  return "no error";
}

TEST(GpioLineOffset, DigitsAreAnOffsetAndAnythingElseIsAName) {
  EXPECT_EQ(gpioLineOffset("17"), 17u);
  EXPECT_EQ(gpioLineOffset("0"), 0u);
  EXPECT_EQ(gpioLineOffset("GPIO17"), std::nullopt);
  EXPECT_EQ(gpioLineOffset("17a"), std::nullopt);
  EXPECT_EQ(gpioLineOffset("-1"), std::nullopt);
  EXPECT_EQ(gpioLineOffset(""), std::nullopt);
  EXPECT_EQ(gpioLineOffset("99999999999999999999"), std::nullopt);
}

TEST(GpiodLed, AnOffsetWithoutAChipIsRefusedBeforeTouchingAnyDevice) {
  EXPECT_THAT(errorOf({"", "17", false}), AllOf(HasSubstr("'17'"), HasSubstr("needs led_chip")));
}

TEST(GpiodLed, AMissingChipIsNamedInTheError) {
  EXPECT_THAT(errorOf({"gpiochip_slicecap_absent", "GPIO17", false}),
              AllOf(HasSubstr("gpiochip_slicecap_absent"), HasSubstr("'GPIO17'"),
                    HasSubstr("cannot open the chip")));
  EXPECT_THAT(errorOf({"/dev/slicecap-no-such-chip", "3", false}),
              AllOf(HasSubstr("/dev/slicecap-no-such-chip"), HasSubstr("'3'")));
}

TEST(GpiodLed, ALineNameFoundOnNoChipIsNamedInTheError) {
  EXPECT_THAT(errorOf({"", "SLICECAP_NO_SUCH_LINE", false}),
              AllOf(HasSubstr("'SLICECAP_NO_SUCH_LINE'"), HasSubstr("any chip"),
                    HasSubstr("no line of that name")));
}

}  // namespace
}  // namespace slicecap::hal
