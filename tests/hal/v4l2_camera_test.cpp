// The V4L2 source's errors without a camera: a missing node and a node that is not a V4L2 device
// are refused with the path in the message.
#include "slicecap/hal/v4l2_camera.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace slicecap::hal {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

TEST(V4l2Camera, AMissingDeviceIsNamedInTheError) {
  EXPECT_THAT([] { V4l2Camera camera("/dev/slicecap-no-such-video"); },
              ::testing::ThrowsMessage<CameraError>(AllOf(
                  HasSubstr("/dev/slicecap-no-such-video"), HasSubstr("cannot open the camera"))));
}

TEST(V4l2Camera, ADeviceThatIsNotAV4l2NodeIsRefused) {
  EXPECT_THAT([] { V4l2Camera camera("/dev/null"); },
              ::testing::ThrowsMessage<CameraError>(
                  AllOf(HasSubstr("/dev/null"), HasSubstr("not a V4L2 device"))));
}

}  // namespace
}  // namespace slicecap::hal
