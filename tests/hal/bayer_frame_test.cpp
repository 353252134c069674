// RAW Bayer decoding against buffers packed by hand from the Linux media documentation's byte
// tables (pixfmt-srggb10p, pixfmt-srggb12p): packing, CFA order, black level, binning, padded
// strides and truncated buffers.
#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/frame.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace slicecap::hal {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// The decoder's mapping of a code to 16-bit linear, written out: (code - black) over
// (largest code - black), from the stored black 4096 to 65535 at the top, clipped at 0.
std::uint16_t linear(double code, double black, double largest) {
  return static_cast<std::uint16_t>(std::lround(
      std::clamp(4096.0 + (code - black) * (65535.0 - 4096.0) / (largest - black), 0.0, 65535.0)));
}

BayerFrameView view(BayerFormat format, int width, int height,
                    const std::vector<std::uint8_t>& bytes, std::size_t stride) {
  BayerFrameView raw;
  raw.format = format;
  raw.widthPx = width;
  raw.heightPx = height;
  raw.bytes = bytes;
  raw.strideBytes = stride;
  return raw;
}

TEST(BayerFrame, Csi2TenBitPacksFourSamplesInFiveBytesLowBitsLast) {
  // RGGB 4 x 2. Row 0: R 1001, Gr 602, R 67, Gr 1023; row 1: Gb 600, B 300, Gb 64, B 1023.
  // Each group: the 8 high bits of 4 samples, then their 2 low bits (sample 0 in bits 1..0).
  // Rows are 8 bytes apart (3 bytes of padding, filled with garbage).
  const std::vector<std::uint8_t> bytes = {
      250, 150, 16, 255, 1 | 2 << 2 | 3 << 4 | 3 << 6, 0xee, 0xee, 0xee,  //
      150, 75, 16, 255, 3 << 6};
  const Image image = decodeBayer(view({BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}, 4, 2,
                                       bytes, 8),
                                  BayerBlackLevels::uniform(4096.0));  // 64 at 10 bits
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 1);
  ASSERT_EQ(image.channels, 3);
  EXPECT_EQ(image.bitDepth, 16);
  EXPECT_EQ(image.at(0, 0, 0), linear(1001, 64, 1023));
  EXPECT_EQ(image.at(0, 0, 1), linear((602 + 600) / 2.0, 64, 1023));
  EXPECT_EQ(image.at(0, 0, 2), linear(300, 64, 1023));
  EXPECT_EQ(image.at(1, 0, 0), linear(67, 64, 1023));
  EXPECT_EQ(image.at(1, 0, 1), linear((1023 + 64) / 2.0, 64, 1023));
  EXPECT_EQ(image.at(1, 0, 2), 65535);
}

TEST(BayerFrame, Csi2TwelveBitPacksTwoSamplesInThreeBytes) {
  // GRBG 2 x 2: row 0 Gr 0xABC, R 0x123; row 1 B 0x0F0, Gb 0xFFF. The third byte holds sample
  // 0's low nibble in bits 3..0 and sample 1's in bits 7..4.
  const std::vector<std::uint8_t> bytes = {0xAB, 0x12, 0x3C, 0x0F, 0xFF, 0xF0};
  const Image image = decodeBayer(view({BayerOrder::Grbg, 12, BayerPacking::Csi2Packed}, 2, 2,
                                       bytes, 3),
                                  BayerBlackLevels::uniform(0.0));
  EXPECT_EQ(image.at(0, 0, 0), linear(0x123, 0, 4095));
  EXPECT_EQ(image.at(0, 0, 1), linear((0xABC + 0xFFF) / 2.0, 0, 4095));
  EXPECT_EQ(image.at(0, 0, 2), linear(0x0F0, 0, 4095));
}

TEST(BayerFrame, UnpackedWordsAreLittleEndianAndEachColourHasItsOwnBlackLevel) {
  // BGGR 12-bit in 16-bit words: B 0x0123, Gb 0x0456 / Gr 0x0789, R 0x0ABC; blacks R 256,
  // Gr 240, Gb 272, B 200 on the 12-bit scale (x16 on the 16-bit scale libcamera reports).
  const std::vector<std::uint8_t> bytes = {0x23, 0x01, 0x56, 0x04, 0x89, 0x07, 0xBC, 0x0A};
  const BayerBlackLevels black{{256 * 16.0, 240 * 16.0, 272 * 16.0, 200 * 16.0}};
  const Image image =
      decodeBayer(view({BayerOrder::Bggr, 12, BayerPacking::Unpacked16}, 2, 2, bytes, 4), black);
  EXPECT_EQ(image.at(0, 0, 0), linear(0x0ABC, 256, 4095));
  const double green = 0.5 * ((0x0789 - 240) * 61439.0 / (4095 - 240) +
                              (0x0456 - 272) * 61439.0 / (4095 - 272));
  EXPECT_EQ(image.at(0, 0, 1), std::lround(4096 + green));
  EXPECT_EQ(image.at(0, 0, 2), linear(0x0123, 200, 4095));
}

TEST(BayerFrame, EveryOrderPutsTheColoursWhereItsNameSays) {
  // A 2 x 2 cell's positions in reading order, coded by the colour the name puts there.
  const std::pair<BayerOrder, const char*> orders[] = {{BayerOrder::Rggb, "RGGB"},
                                                       {BayerOrder::Grbg, "GRBG"},
                                                       {BayerOrder::Gbrg, "GBRG"},
                                                       {BayerOrder::Bggr, "BGGR"}};
  for (const auto& [order, name] : orders) {
    std::vector<std::uint8_t> bytes;
    for (int i = 0; i < 4; ++i) {
      const int code = name[i] == 'R' ? 900 : name[i] == 'G' ? 500 : 100;
      bytes.push_back(static_cast<std::uint8_t>(code & 0xff));
      bytes.push_back(static_cast<std::uint8_t>(code >> 8));
    }
    const Image image = decodeBayer(view({order, 10, BayerPacking::Unpacked16}, 2, 2, bytes, 4),
                                    BayerBlackLevels::uniform(0.0));
    EXPECT_EQ(image.at(0, 0, 0), linear(900, 0, 1023)) << name;
    EXPECT_EQ(image.at(0, 0, 1), linear(500, 0, 1023)) << name;
    EXPECT_EQ(image.at(0, 0, 2), linear(100, 0, 1023)) << name;
  }
}

TEST(BayerFrame, BelowBlackIsKeptUnderTheStoredBlackAndOddEdgesAreDropped) {
  // 3 x 3 RGGB unpacked 10-bit, every sample 60 (4 codes below the black of 64): one pixel out,
  // below the stored black, read as negative light.
  EXPECT_EQ(kDecodedBlack16, 4096);
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < 9; ++i) bytes.insert(bytes.end(), {60, 0});
  const Image image = decodeBayer(view({BayerOrder::Rggb, 10, BayerPacking::Unpacked16}, 3, 3,
                                       bytes, 6),
                                  BayerBlackLevels::uniform(kDefaultBlackLevel16));
  ASSERT_EQ(image.width, 1);
  ASSERT_EQ(image.height, 1);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(image.at(0, 0, c), linear(60, 64, 1023));
    EXPECT_NEAR(linear16Value(image.at(0, 0, c), kDecodedBlack16), -4.0 / (1023 - 64), 1e-5);
  }
  // Only a sample further below black than the stored black clips (a black level near the top).
  const Image far = decodeBayer(view({BayerOrder::Rggb, 10, BayerPacking::Unpacked16}, 3, 3,
                                     bytes, 6),
                                BayerBlackLevels::uniform(900 * 64.0));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(far.at(0, 0, c), 0);
}

// A dark frame (the LED off, the room dark): every sample at the black level plus 0.3 codes,
// with 2.5 codes of read noise (a Pi sensor's at 10 bits). Read as linear light, each channel's
// mean is the truth within its standard error; clipped at black per pixel, as the decoder did
// before, the mean is a whole code too bright (about 0.4 x the read noise), which is 2-3 % of a
// channel near 3 % of full scale once the LED-off frame is subtracted.
TEST(BayerFrame, ADarkFramesMeanIsUnbiasedWhereClippingAtBlackWasNot) {
  const int width = 512, height = 512;
  const double black = 64.0, largest = 1023.0, level = 0.3, readNoise = 2.5;
  std::mt19937 random(44);
  std::normal_distribution<double> noise(black + level, readNoise);
  std::vector<std::uint16_t> codes(std::size_t(width) * height);
  for (std::uint16_t& code : codes)
    code = static_cast<std::uint16_t>(std::clamp(std::lround(noise(random)), 0L, 1023L));
  const BayerFormat format{BayerOrder::Rggb, 10, BayerPacking::Csi2Packed};
  const std::vector<std::uint8_t> bytes = packBayer(format, width, height, codes);
  const Image image = decodeBayer(view(format, width, height, bytes,
                                       minimalBayerStrideBytes(format, width)),
                                  BayerBlackLevels::uniform(black * 64.0));
  const double truth = level / (largest - black);
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0, sum2 = 0.0, clippedSum = 0.0;
    const double n = double(image.width) * image.height;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        const double v = linear16Value(image.at(x, y, c), kDecodedBlack16);
        sum += v;
        sum2 += v * v;
        clippedSum += std::max(v, 0.0);
      }
    const double mean = sum / n;
    const double standardError = std::sqrt((sum2 / n - mean * mean) / n);
    EXPECT_LT(std::abs(mean - truth), 3.0 * standardError)
        << "channel " << c << ": mean " << mean << ", truth " << truth << ", SE " << standardError;
    EXPECT_GT(clippedSum / n - truth, 20.0 * standardError) << "channel " << c;
  }
}

TEST(BayerFrame, ATruncatedBufferNamesTheFormatPlaneAndBytes) {
  // 4 x 2 CSI-2 10-bit, stride 8: the frame needs 8 + 5 bytes.
  const std::vector<std::uint8_t> bytes(12);
  EXPECT_THAT(
      [&] {
        decodeBayer(view({BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}, 4, 2, bytes, 8),
                    BayerBlackLevels::uniform(4096));
      },
      ::testing::ThrowsMessage<RawFrameError>(
          AllOf(HasSubstr("SRGGB10_CSI2P plane 0"), HasSubstr("12 bytes, the frame needs 13"))));
  // A stride below a row's 5 bytes, a black level at the top code, a 1-row mosaic.
  EXPECT_THAT(
      [&] {
        decodeBayer(view({BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}, 4, 2, bytes, 4),
                    BayerBlackLevels::uniform(4096));
      },
      ::testing::ThrowsMessage<RawFrameError>(HasSubstr("stride 4 bytes, below the 5")));
  EXPECT_THROW(decodeBayer(view({BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}, 4, 2,
                                std::vector<std::uint8_t>(16), 8),
                           BayerBlackLevels::uniform(65535.0)),
               RawFrameError);
  EXPECT_THROW(decodeBayer(view({BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}, 4, 1, bytes, 8),
                           BayerBlackLevels::uniform(4096)),
               RawFrameError);
}

TEST(BayerFrame, PackedRowsEndOnWholeGroups) {
  EXPECT_EQ(minimalBayerStrideBytes({BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}, 2304), 2880u);
  EXPECT_EQ(minimalBayerStrideBytes({BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}, 6), 10u);
  EXPECT_EQ(minimalBayerStrideBytes({BayerOrder::Rggb, 12, BayerPacking::Csi2Packed}, 3), 6u);
  EXPECT_EQ(minimalBayerStrideBytes({BayerOrder::Rggb, 12, BayerPacking::Unpacked16}, 3), 6u);
}

TEST(BayerFrame, PackingRoundTripsThroughTheDecoderForEveryFormat) {
  // The camera model packs with packBayer: what it writes must decode to what it meant.
  std::mt19937 random(5);
  for (BayerPacking packing : {BayerPacking::Unpacked16, BayerPacking::Csi2Packed})
    for (int bits : {10, 12, 16}) {
      if (packing == BayerPacking::Csi2Packed && bits == 16) continue;
      const BayerFormat format{BayerOrder::Gbrg, bits, packing};
      const int width = 6, height = 4;
      std::vector<std::uint16_t> codes(std::size_t(width) * height);
      for (std::uint16_t& code : codes)
        code = static_cast<std::uint16_t>(random() % (1u << bits));
      const std::size_t stride = minimalBayerStrideBytes(format, width) + 7;
      const std::vector<std::uint8_t> bytes = packBayer(format, width, height, codes, stride);
      const Image image =
          decodeBayer(view(format, width, height, bytes, stride), BayerBlackLevels::uniform(0));
      const double largest = double((1 << bits) - 1);
      // GBRG: (0,0) Gb, (1,0) B, (0,1) R, (1,1) Gr.
      for (int y = 0; y < height / 2; ++y)
        for (int x = 0; x < width / 2; ++x) {
          const auto code = [&](int dx, int dy) {
            return double(codes[std::size_t(2 * y + dy) * width + 2 * x + dx]);
          };
          EXPECT_EQ(image.at(x, y, 0), linear(code(0, 1), 0, largest)) << bayerFormatName(format);
          EXPECT_EQ(image.at(x, y, 2), linear(code(1, 0), 0, largest)) << bayerFormatName(format);
          EXPECT_NEAR(image.at(x, y, 1), 4096 + (code(0, 0) + code(1, 1)) / 2 * 61439.0 / largest,
                      0.51);
        }
    }
}

TEST(BayerFrame, FormatNamesOfLibcameraAndV4l2) {
  EXPECT_EQ(bayerFormatFromLibcameraName("SRGGB10_CSI2P"),
            (BayerFormat{BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}));
  EXPECT_EQ(bayerFormatFromLibcameraName("SBGGR12"),
            (BayerFormat{BayerOrder::Bggr, 12, BayerPacking::Unpacked16}));
  EXPECT_EQ(bayerFormatFromLibcameraName("SGRBG16"),
            (BayerFormat{BayerOrder::Grbg, 16, BayerPacking::Unpacked16}));
  EXPECT_FALSE(bayerFormatFromLibcameraName("SRGGB16_CSI2P"));
  EXPECT_FALSE(bayerFormatFromLibcameraName("SRGGB10_IPU3"));
  EXPECT_FALSE(bayerFormatFromLibcameraName("YUYV"));
  EXPECT_EQ(bayerFormatFromV4l2(v4l2_fourcc('p', 'R', 'A', 'A')),
            (BayerFormat{BayerOrder::Rggb, 10, BayerPacking::Csi2Packed}));
  EXPECT_EQ(bayerFormatFromV4l2(v4l2_fourcc('p', 'B', 'C', 'C')),
            (BayerFormat{BayerOrder::Bggr, 12, BayerPacking::Csi2Packed}));
  EXPECT_EQ(bayerFormatFromV4l2(v4l2_fourcc('B', 'A', '1', '0')),
            (BayerFormat{BayerOrder::Grbg, 10, BayerPacking::Unpacked16}));
  EXPECT_FALSE(bayerFormatFromV4l2(v4l2_fourcc('Y', 'U', 'Y', 'V')));
}

TEST(BayerFrame, ThePiFivesCompressedRawIsNamedWithTheFallback) {
  EXPECT_TRUE(isRawFormatName("RGGB_PISP_COMP1"));
  EXPECT_TRUE(isRawFormatName("SBGGR10_IPU3"));
  EXPECT_TRUE(isRawFormatName("SRGGB12_CSI2P"));
  EXPECT_FALSE(isRawFormatName("YUV420"));
  EXPECT_FALSE(isRawFormatName("SRGB"));
  EXPECT_EQ(undecodableRawReason("SRGGB10_CSI2P"), "");
  EXPECT_THAT(undecodableRawReason("BGGR_PISP_COMP1"),
              AllOf(HasSubstr("BGGR_PISP_COMP1"), HasSubstr("PiSP compressed"),
                    HasSubstr("processed stream")));
  EXPECT_THAT(undecodableRawReason("SRGGB10_IPU3"),
              AllOf(HasSubstr("SRGGB10_IPU3"), HasSubstr("processed stream")));
}

TEST(BayerFrame, APackedFormatsUnpackedTwinIsOneTheDecoderReads) {
  EXPECT_EQ(unpackedRawFormatName("SRGGB10_CSI2P"), "SRGGB10");
  EXPECT_EQ(unpackedRawFormatName("SGBRG12_CSI2P"), "SGBRG12");
  // The Pi 5's compressed formats: what its frontend writes uncompressed, 16-bit words.
  EXPECT_EQ(unpackedRawFormatName("BGGR_PISP_COMP1"), "SBGGR16");
  EXPECT_EQ(unpackedRawFormatName("RGGB_PISP_COMP1"), "SRGGB16");
  for (const char* twin : {"SRGGB10", "SGBRG12", "SBGGR16", "SRGGB16"}) {
    const std::optional<BayerFormat> format = bayerFormatFromLibcameraName(twin);
    ASSERT_TRUE(format) << twin;
    EXPECT_EQ(format->packing, BayerPacking::Unpacked16) << twin;
  }
  EXPECT_FALSE(unpackedRawFormatName("SRGGB10"));
  EXPECT_FALSE(unpackedRawFormatName("SRGGB10_IPU3"));
  EXPECT_FALSE(unpackedRawFormatName("MONO_PISP_COMP1"));
  EXPECT_FALSE(unpackedRawFormatName("YUYV"));
}

TEST(BayerFrame, TheSensorModeIsTheOneWhoseBinnedSizeFitsTheRequest) {
  // IMX708 (camera module 3) and IMX219 (v2) modes as libcamera lists them.
  const std::vector<std::pair<int, int>> imx708 = {{1536, 864}, {2304, 1296}, {4608, 2592}};
  EXPECT_EQ(chooseBayerSize(imx708, 1280, 720), (std::pair{2304, 1296}));
  EXPECT_EQ(chooseBayerSize(imx708, 2304, 1296), (std::pair{4608, 2592}));
  const std::vector<std::pair<int, int>> imx219 = {
      {640, 480}, {1640, 1232}, {1920, 1080}, {3280, 2464}};
  EXPECT_EQ(chooseBayerSize(imx219, 1280, 720), (std::pair{1920, 1080}));
  EXPECT_EQ(chooseBayerSize(imx219, 800, 600), (std::pair{1640, 1232}));
  EXPECT_FALSE(chooseBayerSize({}, 1280, 720));
}

}  // namespace
}  // namespace slicecap::hal
