// The libcamera source without a camera: its errors name what is missing, and the process's one
// CameraManager is shared, so asking twice (or from two threads) does not abort the process, as
// two live managers would.
#include "slicecap/hal/libcamera_camera.hpp"

#include <libcamera/formats.h>

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

// The RAW formats are chosen by libcamera's names for them (PixelFormat::toString), which this
// installed libcamera must spell as the decoder expects.
TEST(LibcameraCamera, LibcamerasRawFormatNamesMapToTheDecodersFormats) {
  namespace f = libcamera::formats;
  using O = BayerOrder;
  using P = BayerPacking;
  const std::pair<libcamera::PixelFormat, BayerFormat> decodable[] = {
      {f::SRGGB10_CSI2P, {O::Rggb, 10, P::Csi2Packed}}, {f::SGRBG10_CSI2P, {O::Grbg, 10, P::Csi2Packed}},
      {f::SGBRG10_CSI2P, {O::Gbrg, 10, P::Csi2Packed}}, {f::SBGGR10_CSI2P, {O::Bggr, 10, P::Csi2Packed}},
      {f::SRGGB12_CSI2P, {O::Rggb, 12, P::Csi2Packed}}, {f::SBGGR12_CSI2P, {O::Bggr, 12, P::Csi2Packed}},
      {f::SRGGB10, {O::Rggb, 10, P::Unpacked16}},       {f::SGBRG12, {O::Gbrg, 12, P::Unpacked16}},
      {f::SRGGB16, {O::Rggb, 16, P::Unpacked16}},       {f::SBGGR16, {O::Bggr, 16, P::Unpacked16}}};
  for (const auto& [format, expected] : decodable) {
    EXPECT_TRUE(isRawFormatName(format.toString())) << format.toString();
    EXPECT_EQ(bayerFormatFromLibcameraName(format.toString()), expected) << format.toString();
  }
  EXPECT_TRUE(isRawFormatName(f::SRGGB10_IPU3.toString()));
  EXPECT_FALSE(bayerFormatFromLibcameraName(f::SRGGB10_IPU3.toString()));
  for (const libcamera::PixelFormat& processed : {f::YUYV, f::YUV420, f::RGB888, f::XRGB8888})
    EXPECT_FALSE(isRawFormatName(processed.toString())) << processed.toString();
}

}  // namespace
}  // namespace slicecap::hal
