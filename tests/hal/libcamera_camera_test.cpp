// The libcamera source without a camera: its errors name what is missing, and the process's one
// CameraManager is shared, so asking twice (or from two threads) does not abort the process, as
// two live managers would.
#include "slicecap/hal/libcamera_camera.hpp"

#include <libcamera/color_space.h>
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
  // The RAW negotiation asks for formats by name (PixelFormat::fromString), among them the
  // unpacked twins a Pi 5 grants.
  for (const libcamera::PixelFormat& twin : {f::SRGGB10, f::SBGGR12, f::SRGGB16, f::SGRBG16})
    EXPECT_EQ(libcamera::PixelFormat::fromString(twin.toString()), twin) << twin.toString();
  EXPECT_EQ(libcamera::PixelFormat::fromString(*unpackedRawFormatName("SRGGB10_CSI2P")), f::SRGGB10);
  EXPECT_TRUE(isRawFormatName(f::SRGGB10_IPU3.toString()));
  EXPECT_FALSE(bayerFormatFromLibcameraName(f::SRGGB10_IPU3.toString()));
  for (const libcamera::PixelFormat& processed : {f::YUYV, f::YUV420, f::RGB888, f::XRGB8888})
    EXPECT_FALSE(isRawFormatName(processed.toString())) << processed.toString();
}

// The colour spaces libcamera's ColorSpace names (the same in 0.0.3 and the Raspberry Pi fork):
// a YUV stream is decoded by its own matrix and range, an RGB or RAW one has none to give.
TEST(LibcameraCamera, AStreamsColourSpaceGivesItsYuvMatrixAndRange) {
  using C = libcamera::ColorSpace;
  using E = YuvEncoding;
  EXPECT_EQ(yuvEncodingOf(C::Rec709), (E{YcbcrMatrix::Rec709, YuvRange::Limited}));
  EXPECT_EQ(yuvEncodingOf(C::Sycc), (E{YcbcrMatrix::Rec601, YuvRange::Full}));
  EXPECT_EQ(yuvEncodingOf(C::Smpte170m), (E{YcbcrMatrix::Rec601, YuvRange::Limited}));
  EXPECT_EQ(yuvEncodingOf(C::Rec2020), (E{YcbcrMatrix::Rec2020, YuvRange::Limited}));
  // The Pi 5's "rec709_full" (libpisp's backend_default_config.json).
  C fullRec709 = C::Rec709;
  fullRec709.range = C::Range::Full;
  EXPECT_EQ(yuvEncodingOf(fullRec709), (E{YcbcrMatrix::Rec709, YuvRange::Full}));
  EXPECT_FALSE(yuvEncodingOf(C::Srgb));
  EXPECT_FALSE(yuvEncodingOf(C::Raw));
}

}  // namespace
}  // namespace slicecap::hal
