// The libcamera source without a camera: its errors name what is missing, and the process's one
// CameraManager is shared, so asking twice (or from two threads) does not abort the process, as
// two live managers would.
#include "slicecap/hal/libcamera_camera.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <thread>

namespace slicecap::hal {
namespace {

using ::testing::HasSubstr;

// libcamera logs every manager start at INFO; the tests only need its errors.
const bool kQuietLibcamera = [] { return ::setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 0) == 0; }();

TEST(LibcameraCamera, AnUnknownCameraIdIsNamedInTheError) {
  EXPECT_THAT([] { LibcameraCamera camera("slicecap-no-such-camera"); },
              ::testing::ThrowsMessage<CameraError>(HasSubstr("'slicecap-no-such-camera'")));
}

TEST(LibcameraCamera, ManyUsersShareOneCameraManager) {
  const std::vector<std::string> first = listLibcameraCameras();
  std::vector<std::string> fromThreads[4];
  {
    std::vector<std::jthread> threads;
    for (auto& ids : fromThreads) threads.emplace_back([&ids] { ids = listLibcameraCameras(); });
  }
  for (const auto& ids : fromThreads) EXPECT_EQ(ids, first);
  // A camera object alive while another listing runs: still one manager.
  try {
    LibcameraCamera camera("");
    EXPECT_EQ(listLibcameraCameras(), first);
  } catch (const CameraError& error) {
    EXPECT_TRUE(first.empty()) << error.what();
    EXPECT_THAT(error.what(), HasSubstr("no camera found"));
  }
}

}  // namespace
}  // namespace slicecap::hal
