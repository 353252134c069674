// Camera buffer conversions: colours of known YUV values, channel order, padded strides, and
// buffers too small for their frame.
#include "slicecap/hal/raw_frame.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

namespace slicecap::hal {
namespace {

using ::testing::HasSubstr;

constexpr YuvEncoding kRec601Limited{YcbcrMatrix::Rec601, YuvRange::Limited};

RawFrameView packedView(RawLayout layout, int width, int height, const std::vector<std::uint8_t>& bytes,
                        std::size_t stride, std::optional<YuvEncoding> yuv = kRec601Limited) {
  RawFrameView view;
  view.layout = layout;
  view.widthPx = width;
  view.heightPx = height;
  view.planes[0] = bytes;
  view.strideBytes[0] = stride;
  view.yuv = yuv;
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
  view.yuv = kRec601Limited;
  const Image image = toImage(view);
  EXPECT_EQ(image.at(1, 1, 1), 255);  // white, neutral chroma
  EXPECT_GE(image.at(2, 1, 0), 253);  // red
  EXPECT_LE(image.at(2, 1, 1), 2);
}

// The reference: R'G'B' (0..255) encoded to 8-bit Y'CbCr from the ITU-R formulas, written here
// from BT.601-7, BT.709-6 and BT.2020-2 (E'Y = Kr R' + (1 - Kr - Kb) G' + Kb B',
// E'Cb = (B' - E'Y) / (2 (1 - Kb)), E'Cr = (R' - E'Y) / (2 (1 - Kr)); limited quantisation
// Y = 16 + 219 E'Y, C = 128 + 224 E'C; full, as sYCC and JFIF, Y = 255 E'Y, C = 128 + 255 E'C),
// not from the decoder's inverse.
std::array<std::uint8_t, 3> encode(std::array<int, 3> rgb, double kr, double kb, bool limited) {
  const double r = rgb[0] / 255.0, g = rgb[1] / 255.0, b = rgb[2] / 255.0;
  const double y = kr * r + (1.0 - kr - kb) * g + kb * b;
  const double cb = (b - y) / (2.0 * (1.0 - kb)), cr = (r - y) / (2.0 * (1.0 - kr));
  const auto byte = [](double v) { return std::uint8_t(std::clamp(std::lround(v), 0L, 255L)); };
  return limited ? std::array{byte(16 + 219 * y), byte(128 + 224 * cb), byte(128 + 224 * cr)}
                 : std::array{byte(255 * y), byte(128 + 255 * cb), byte(128 + 255 * cr)};
}

// One YUYV pixel pair per colour (both pixels the same), decoded as `decodedAs`.
Image decodeColours(const std::vector<std::array<int, 3>>& colours, double kr, double kb,
                    bool limited, YuvEncoding decodedAs) {
  std::vector<std::uint8_t> bytes;
  for (const auto& rgb : colours) {
    const auto [y, u, v] = encode(rgb, kr, kb, limited);
    bytes.insert(bytes.end(), {y, u, y, v});
  }
  const int width = int(2 * colours.size());
  return toImage(packedView(RawLayout::Yuyv, width, 1, bytes, bytes.size(), decodedAs));
}

// The largest difference of any channel of any colour from the R'G'B' it was encoded from.
int largestError(const Image& image, const std::vector<std::array<int, 3>>& colours) {
  int worst = 0;
  for (std::size_t i = 0; i < colours.size(); ++i)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(int(image.at(int(2 * i), 0, c)) - colours[i][c]));
  return worst;
}

const std::vector<std::array<int, 3>> kColours = {
    {0, 0, 0},     {64, 64, 64},  {128, 128, 128}, {200, 200, 200}, {255, 255, 255},
    {255, 0, 0},   {0, 255, 0},   {0, 0, 255},     {180, 40, 60},   {30, 140, 220}};

TEST(RawFrame, YuvDecodesByItsOwnMatrixAndRangeToTheRgbItWasEncodedFrom) {
  struct Case {
    YuvEncoding encoding;
    double kr, kb;
  };
  const Case cases[] = {
      {{YcbcrMatrix::Rec601, YuvRange::Limited}, 0.299, 0.114},    // SMPTE 170M
      {{YcbcrMatrix::Rec601, YuvRange::Full}, 0.299, 0.114},       // sYCC, JPEG
      {{YcbcrMatrix::Rec709, YuvRange::Limited}, 0.2126, 0.0722},  // the Pi's HD video
      {{YcbcrMatrix::Rec709, YuvRange::Full}, 0.2126, 0.0722},
      {{YcbcrMatrix::Rec2020, YuvRange::Limited}, 0.2627, 0.0593},
  };
  for (const Case& c : cases) {
    const bool limited = c.encoding.range == YuvRange::Limited;
    // 8-bit Y'CbCr rounds each component: within a code either way.
    EXPECT_LE(largestError(decodeColours(kColours, c.kr, c.kb, limited, c.encoding), kColours), 1)
        << toString(c.encoding);
  }
}

TEST(RawFrame, DecodingEveryYuvAsBt601LimitedGetsTheHdAndFullRangeStreamsWrong) {
  // What every YUV frame was decoded as before the stream's colour space was read.
  const std::vector<std::array<int, 3>> red = {{255, 0, 0}};
  const Image rec709 = decodeColours(red, 0.2126, 0.0722, true, kRec601Limited);
  EXPECT_GT(std::abs(int(rec709.at(0, 0, 0)) - 255), 15);  // R of a saturated red: 233
  EXPECT_EQ(decodeColours(red, 0.2126, 0.0722, true, {YcbcrMatrix::Rec709, YuvRange::Limited})
                .at(0, 0, 0),
            255);
  const std::vector<std::array<int, 3>> magenta = {{200, 60, 200}};
  EXPECT_GT(largestError(decodeColours(magenta, 0.2126, 0.0722, true, kRec601Limited), magenta),
            10);
  // A full-range grey read as limited: 200 comes out 14 codes (about 7 %) too bright.
  const std::vector<std::array<int, 3>> grey = {{200, 200, 200}};
  EXPECT_GE(largestError(decodeColours(grey, 0.299, 0.114, false, kRec601Limited), grey), 10);
}

TEST(RawFrame, AYuvFrameWithoutItsMatrixAndRangeIsNotDecodedByAGuess) {
  const std::vector<std::uint8_t> bytes = {16, 128, 235, 128};
  EXPECT_THAT([&] { toImage(packedView(RawLayout::Yuyv, 2, 1, bytes, 4, std::nullopt)); },
              ::testing::ThrowsMessage<RawFrameError>(HasSubstr("YCbCr matrix and range")));
  EXPECT_EQ(toString(YuvEncoding{YcbcrMatrix::Rec709, YuvRange::Limited}), "Rec.709 limited range");
  EXPECT_TRUE(isYuv(RawLayout::Yuv420));
  EXPECT_FALSE(isYuv(RawLayout::Rgb24));
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
