// The backend factories: a backend this build has opens its device (here: fails on a device that
// is not there, with the device's own error); one it does not have names its CMake option.
#include "slicecap/hal/device_backends.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>

#include "slicecap/hal/camera_error.hpp"

namespace slicecap::hal {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// What opening the backend's device throws: "not built: <what>" or "device: <what>".
std::string openingFails(const std::function<void()>& open) {
  try {
    open();
  } catch (const BackendNotBuilt& error) {
    return std::string("not built: ") + error.what();
  } catch (const slicecap::Error& error) {
    return std::string("device: ") + error.what();
  }
  return "opened";
}

// Each backend with a way to open a device that exists on no build machine.
struct Case {
  DeviceBackend backend;
  std::function<void()> open;
};

std::vector<Case> cases() {
  return {{DeviceBackend::Libcamera, [] { openLibcameraCamera("slicecap-no-such-camera"); }},
          {DeviceBackend::V4l2, [] { openV4l2Camera("/dev/slicecap-no-such-video"); }},
          {DeviceBackend::Gpiod, [] { openGpiodLed({"slicecap-no-such-chip", "GPIO17", false}); }}};
}

TEST(DeviceBackends, ABackendNotBuiltNamesItselfAndItsCMakeOption) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(backendName(c.backend));
    const std::string outcome = openingFails(c.open);
    if (isBuilt(c.backend)) {
      // The device's own error (no such camera, device or chip), never the build's.
      EXPECT_THAT(outcome, HasSubstr("device: "));
    } else {
      EXPECT_THAT(outcome, AllOf(HasSubstr("not built: " + backendName(c.backend) + ": "),
                                 HasSubstr("-D" + backendOption(c.backend) + "=ON")));
    }
  }
}

TEST(DeviceBackends, ListingModesOfABackendNotBuiltNamesItsOption) {
  if (isBuilt(DeviceBackend::V4l2)) {
    EXPECT_THAT(openingFails([] { v4l2Modes("/dev/slicecap-no-such-video"); }),
                HasSubstr("device: "));
  } else {
    EXPECT_THAT(openingFails([] { v4l2Modes("/dev/video0"); }),
                HasSubstr("-DSLICECAP_WITH_V4L2=ON"));
  }
  if (!isBuilt(DeviceBackend::Libcamera)) {
    EXPECT_THAT(openingFails([] { libcameraModes(1280, 720); }), HasSubstr("-DSLICECAP_WITH_LIBCAMERA=ON"));
  }
}

TEST(DeviceBackends, RequireBuiltThrowsExactlyForTheBackendsNotBuilt) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(backendName(c.backend));
    if (isBuilt(c.backend))
      EXPECT_NO_THROW(requireBuilt(c.backend));
    else
      EXPECT_THROW(requireBuilt(c.backend), BackendNotBuilt);
  }
}

}  // namespace
}  // namespace slicecap::hal
