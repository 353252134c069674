// Camera buffer conversions: colours of known YUV values, channel order, padded strides, and
// buffers too small for their frame.
#include "slicecap/hal/raw_frame.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <vector>

namespace slicecap::hal {
namespace {

using ::testing::HasSubstr;

RawFrameView packedView(RawLayout layout, int width, int height, const std::vector<std::uint8_t>& bytes,
                        std::size_t stride) {
  RawFrameView view;
  view.layout = layout;
  view.widthPx = width;
  view.heightPx = height;
  view.planes[0] = bytes;
  view.strideBytes[0] = stride;
  return view;
}

TEST(RawFrame, YuyvLimitedRangeMapsBlackWhiteAndRed) {
  // Two pixel pairs: (black, white) with neutral chroma, then BT.601 red (Y 81, U 90, V 240).
  const std::vector<std::uint8_t> bytes = {16, 128, 235, 128, 81, 90, 81, 240};
  const Image image = toImage(packedView(RawLayout::Yuyv, 4, 1, bytes, 8));
  ASSERT_EQ(image.channels, 3);
  EXPECT_EQ(image.bitDepth, 8);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(image.at(0, 0, c), 0);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(image.at(1, 0, c), 255);
  EXPECT_GE(image.at(2, 0, 0), 253);
  EXPECT_LE(image.at(2, 0, 1), 2);
  EXPECT_LE(image.at(2, 0, 2), 2);
}

TEST(RawFrame, BgrLayoutsComeOutAsRgbAndPaddingIsSkipped) {
  // Two rows of one pixel, stride 8 (5 bytes of padding after each B,G,R).
  const std::vector<std::uint8_t> bytes = {1, 2, 3, 99, 99, 99, 99, 99, 4, 5, 6};
  const Image image = toImage(packedView(RawLayout::Bgr24, 1, 2, bytes, 8));
  EXPECT_EQ(image.at(0, 0, 0), 3);
  EXPECT_EQ(image.at(0, 0, 2), 1);
  EXPECT_EQ(image.at(0, 1, 0), 6);
  EXPECT_EQ(image.at(0, 1, 1), 5);
  const std::vector<std::uint8_t> bgrx = {10, 20, 30, 255};
  const Image fromBgrx = toImage(packedView(RawLayout::Bgrx32, 1, 1, bgrx, 4));
  EXPECT_EQ(fromBgrx.at(0, 0, 0), 30);
  EXPECT_EQ(fromBgrx.at(0, 0, 2), 10);
}

TEST(RawFrame, Y16IsLittleEndianLinearSixteenBit) {
  const std::vector<std::uint8_t> bytes = {0x34, 0x12, 0xff, 0xff};
  const Image image = toImage(packedView(RawLayout::Y16, 2, 1, bytes, 4));
  EXPECT_EQ(image.bitDepth, 16);
  EXPECT_EQ(image.channels, 1);
  EXPECT_EQ(image.at(0, 0, 0), 0x1234);
  EXPECT_EQ(image.at(1, 0, 0), 0xffff);
  EXPECT_EQ(encodingOf(RawLayout::Y16), PixelEncoding::Linear16);
  EXPECT_EQ(encodingOf(RawLayout::Yuyv), PixelEncoding::Srgb8);
}

TEST(RawFrame, Yuv420SharesEachChromaSampleAmongTwoByTwoPixels) {
  // 3 x 2 pixels: chroma planes are 2 x 1; the right chroma sample is red, the left neutral.
  const std::vector<std::uint8_t> luma = {235, 235, 81, 235, 235, 81};
  const std::vector<std::uint8_t> u = {128, 90};
  const std::vector<std::uint8_t> v = {128, 240};
  RawFrameView view;
  view.layout = RawLayout::Yuv420;
  view.widthPx = 3;
  view.heightPx = 2;
  view.planes[0] = luma;
  view.planes[1] = u;
  view.planes[2] = v;
  view.strideBytes[0] = 3;
  view.strideBytes[1] = 2;
  view.strideBytes[2] = 2;
  const Image image = toImage(view);
  EXPECT_EQ(image.at(1, 1, 1), 255);  // white, neutral chroma
  EXPECT_GE(image.at(2, 1, 0), 253);  // red
  EXPECT_LE(image.at(2, 1, 1), 2);
}

TEST(RawFrame, ABufferTooSmallForItsFrameIsAnErrorNamingThePlane) {
  const std::vector<std::uint8_t> bytes(4 * 2 * 3 - 1);
  EXPECT_THAT(
      [&] { toImage(packedView(RawLayout::Yuyv, 4, 3, bytes, 8)); },
      ::testing::ThrowsMessage<RawFrameError>(HasSubstr("YUYV plane 0: 23 bytes")));
  EXPECT_THROW(toImage(packedView(RawLayout::Rgb24, 4, 1, std::vector<std::uint8_t>(12), 6)),
               RawFrameError);
  EXPECT_THROW(toImage(packedView(RawLayout::Grey8, 0, 1, std::vector<std::uint8_t>(1), 1)),
               RawFrameError);
}

}  // namespace
}  // namespace slicecap::hal
