// Bayer unpacking, black level and 2 x 2 binning.
#include "slicecap/hal/bayer_frame.hpp"

#include <linux/videodev2.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "slicecap/hal/hal_error.hpp"

namespace slicecap::hal {
namespace {

// Channel indices in BayerBlackLevels' order.
constexpr int kR = 0, kGr = 1, kGb = 2, kB = 3;

/// The channel at (column parity, row parity) of a 2 x 2 cell.
std::array<std::array<int, 2>, 2> cellChannels(BayerOrder order) {
  switch (order) {
    case BayerOrder::Rggb: return {{{kR, kGr}, {kGb, kB}}};
    case BayerOrder::Grbg: return {{{kGr, kR}, {kB, kGb}}};
    case BayerOrder::Gbrg: return {{{kGb, kB}, {kR, kGr}}};
    case BayerOrder::Bggr: return {{{kB, kGb}, {kGr, kR}}};
  }
  return {{{kR, kGr}, {kGb, kB}}};
}

std::string_view orderName(BayerOrder order) {
  switch (order) {
    case BayerOrder::Rggb: return "RGGB";
    case BayerOrder::Grbg: return "GRBG";
    case BayerOrder::Gbrg: return "GBRG";
    case BayerOrder::Bggr: return "BGGR";
  }
  return "RGGB";
}

constexpr BayerOrder kOrders[] = {BayerOrder::Rggb, BayerOrder::Grbg, BayerOrder::Gbrg,
                                  BayerOrder::Bggr};

bool isValidFormat(const BayerFormat& format) {
  if (format.packing == BayerPacking::Csi2Packed)
    return format.bitDepth == 10 || format.bitDepth == 12;
  return format.bitDepth == 10 || format.bitDepth == 12 || format.bitDepth == 16;
}

/// One row of samples as codes, clamped to the format's largest code (an unpacked word with
/// bits above the depth is a driver's garbage, not a brighter pixel).
void unpackRow(const BayerFormat& format, const std::uint8_t* row, int widthPx,
               std::uint16_t* codes) {
  const int largest = (1 << format.bitDepth) - 1;
  if (format.packing == BayerPacking::Unpacked16) {
    for (int x = 0; x < widthPx; ++x)
      codes[x] = static_cast<std::uint16_t>(
          std::min<int>(row[2 * x] | (row[2 * x + 1] << 8), largest));
  } else if (format.bitDepth == 10) {
    for (int x = 0; x < widthPx; ++x) {
      const std::uint8_t* group = row + 5 * (x / 4);
      const int k = x % 4;
      codes[x] = static_cast<std::uint16_t>((group[k] << 2) | ((group[4] >> (2 * k)) & 0x3));
    }
  } else {
    for (int x = 0; x < widthPx; ++x) {
      const std::uint8_t* group = row + 3 * (x / 2);
      const int k = x % 2;
      codes[x] = static_cast<std::uint16_t>((group[k] << 4) | ((group[2] >> (4 * k)) & 0xf));
    }
  }
}

}  // namespace

std::string bayerFormatName(const BayerFormat& format) {
  std::string name = "S" + std::string(orderName(format.order)) + std::to_string(format.bitDepth);
  if (format.packing == BayerPacking::Csi2Packed) name += "_CSI2P";
  return name;
}

std::optional<BayerFormat> bayerFormatFromLibcameraName(std::string_view name) {
  for (BayerOrder order : kOrders)
    for (BayerPacking packing : {BayerPacking::Unpacked16, BayerPacking::Csi2Packed})
      for (int bits : {10, 12, 16}) {
        const BayerFormat format{order, bits, packing};
        if (isValidFormat(format) && bayerFormatName(format) == name) return format;
      }
  return std::nullopt;
}

std::optional<BayerFormat> bayerFormatFromV4l2(std::uint32_t fourcc) {
  using P = BayerPacking;
  using O = BayerOrder;
  struct Entry {
    std::uint32_t fourcc;
    BayerFormat format;
  };
  static const Entry kEntries[] = {
      {V4L2_PIX_FMT_SRGGB10, {O::Rggb, 10, P::Unpacked16}},
      {V4L2_PIX_FMT_SGRBG10, {O::Grbg, 10, P::Unpacked16}},
      {V4L2_PIX_FMT_SGBRG10, {O::Gbrg, 10, P::Unpacked16}},
      {V4L2_PIX_FMT_SBGGR10, {O::Bggr, 10, P::Unpacked16}},
      {V4L2_PIX_FMT_SRGGB12, {O::Rggb, 12, P::Unpacked16}},
      {V4L2_PIX_FMT_SGRBG12, {O::Grbg, 12, P::Unpacked16}},
      {V4L2_PIX_FMT_SGBRG12, {O::Gbrg, 12, P::Unpacked16}},
      {V4L2_PIX_FMT_SBGGR12, {O::Bggr, 12, P::Unpacked16}},
      {V4L2_PIX_FMT_SRGGB16, {O::Rggb, 16, P::Unpacked16}},
      {V4L2_PIX_FMT_SGRBG16, {O::Grbg, 16, P::Unpacked16}},
      {V4L2_PIX_FMT_SGBRG16, {O::Gbrg, 16, P::Unpacked16}},
      {V4L2_PIX_FMT_SBGGR16, {O::Bggr, 16, P::Unpacked16}},
      {V4L2_PIX_FMT_SRGGB10P, {O::Rggb, 10, P::Csi2Packed}},
      {V4L2_PIX_FMT_SGRBG10P, {O::Grbg, 10, P::Csi2Packed}},
      {V4L2_PIX_FMT_SGBRG10P, {O::Gbrg, 10, P::Csi2Packed}},
      {V4L2_PIX_FMT_SBGGR10P, {O::Bggr, 10, P::Csi2Packed}},
      {V4L2_PIX_FMT_SRGGB12P, {O::Rggb, 12, P::Csi2Packed}},
      {V4L2_PIX_FMT_SGRBG12P, {O::Grbg, 12, P::Csi2Packed}},
      {V4L2_PIX_FMT_SGBRG12P, {O::Gbrg, 12, P::Csi2Packed}},
      {V4L2_PIX_FMT_SBGGR12P, {O::Bggr, 12, P::Csi2Packed}},
  };
  for (const Entry& entry : kEntries)
    if (entry.fourcc == fourcc) return entry.format;
  return std::nullopt;
}

bool isRawFormatName(std::string_view name) {
  if (name.find("_PISP_COMP") != std::string_view::npos) return true;
  // S + a CFA order + a bit depth, e.g. SRGGB10, SBGGR12_CSI2P, SGRBG10_IPU3.
  if (name.size() < 6 || name[0] != 'S') return false;
  for (BayerOrder order : kOrders)
    if (name.substr(1, 4) == orderName(order))
      return name.size() > 5 && name[5] >= '0' && name[5] <= '9';
  return false;
}

std::string undecodableRawReason(std::string_view name) {
  if (bayerFormatFromLibcameraName(name)) return "";
  const std::string quoted(name);
  if (name.find("_PISP_COMP") != std::string_view::npos)
    return "RAW format " + quoted +
           " is the Raspberry Pi 5's PiSP compressed Bayer (a lossy coding slicecap does not "
           "decode): the processed stream is used instead (set camera_raw = off to choose that "
           "without this message)";
  return "RAW format " + quoted + " is not one slicecap decodes (it decodes SRGGB10/12/16 and " +
         "SRGGB10/12_CSI2P in any CFA order): the processed stream is used instead";
}

std::optional<std::string> unpackedRawFormatName(std::string_view name) {
  if (const std::optional<BayerFormat> format = bayerFormatFromLibcameraName(name);
      format && format->packing == BayerPacking::Csi2Packed)
    return bayerFormatName({format->order, format->bitDepth, BayerPacking::Unpacked16});
  // RGGB_PISP_COMP1 and the other orders (and MONO_PISP_COMP1, which slicecap does not take).
  if (const auto pisp = name.find("_PISP_COMP"); pisp != std::string_view::npos)
    for (BayerOrder order : kOrders)
      if (name.substr(0, pisp) == orderName(order))
        return bayerFormatName({order, 16, BayerPacking::Unpacked16});
  return std::nullopt;
}

std::size_t minimalBayerStrideBytes(const BayerFormat& format, int widthPx) {
  const auto width = static_cast<std::size_t>(std::max(widthPx, 0));
  if (format.packing == BayerPacking::Unpacked16) return 2 * width;
  if (format.bitDepth == 10) return 5 * ((width + 3) / 4);
  return 3 * ((width + 1) / 2);
}

std::optional<std::pair<int, int>> chooseBayerSize(const std::vector<std::pair<int, int>>& offered,
                                                   int wantedWidthPx, int wantedHeightPx) {
  std::optional<std::pair<int, int>> best;
  double bestAspect = 0.0, bestScale = 0.0;
  const double wantedAspect = double(wantedWidthPx) / std::max(wantedHeightPx, 1);
  const double wantedArea = double(wantedWidthPx) * wantedHeightPx;
  for (const auto& [width, height] : offered) {
    if (width < 2 || height < 2) continue;
    const double binnedW = width / 2, binnedH = height / 2;
    // An aspect ratio within 1 % counts as the same (sensor modes round their sizes).
    const double aspectMiss = std::abs(std::log(binnedW / binnedH / wantedAspect));
    const double aspect = aspectMiss < 0.01 ? 0.0 : aspectMiss;
    const double scale = std::abs(std::log(binnedW * binnedH / wantedArea));
    if (!best || aspect < bestAspect || (aspect == bestAspect && scale < bestScale)) {
      best = std::pair{width, height};
      bestAspect = aspect;
      bestScale = scale;
    }
  }
  return best;
}

namespace {

// Refuses a format slicecap does not decode, a frame below one 2 x 2 cell, and a plane too small
// for its rows.
void checkBayerFrame(const BayerFrameView& raw, const std::string& name) {
  if (!isValidFormat(raw.format))
    throw RawFrameError(name + ": " + std::to_string(raw.format.bitDepth) +
                        "-bit samples in this packing are not a format slicecap decodes");
  if (raw.widthPx < 2 || raw.heightPx < 2)
    throw RawFrameError(name + " frame of " + std::to_string(raw.widthPx) + " x " +
                        std::to_string(raw.heightPx) + " pixels: a mosaic needs 2 x 2 at least");
  const std::size_t minimal = minimalBayerStrideBytes(raw.format, raw.widthPx);
  if (raw.strideBytes < minimal)
    throw RawFrameError(name + " plane 0: stride " + std::to_string(raw.strideBytes) +
                        " bytes, below the " + std::to_string(minimal) + " a row needs");
  const std::size_t needed = raw.strideBytes * std::size_t(raw.heightPx - 1) + minimal;
  if (raw.bytes.size() < needed)
    throw RawFrameError(name + " plane 0: " + std::to_string(raw.bytes.size()) +
                        " bytes, the frame needs " + std::to_string(needed));
}

// Black and scale per channel (kR, kGr, kGb, kB), on the sample's own scale.
struct ChannelLevels {
  std::array<double, 4> offset{}, range{};
};

// The decoded samples' span above kDecodedBlack16: the sensor's largest code lands on 65535.
constexpr double kDecodedSpan = 65535.0 - kDecodedBlack16;

ChannelLevels channelLevels(const BayerFormat& format, const BayerBlackLevels& black,
                            const std::string& name) {
  const double largest = double((1 << format.bitDepth) - 1);
  const double toSampleScale = std::ldexp(1.0, format.bitDepth - 16);
  ChannelLevels levels;
  for (int c = 0; c < 4; ++c) {
    levels.offset[c] = black.levels16[c] * toSampleScale;
    if (!(levels.offset[c] >= 0.0 && levels.offset[c] < largest))
      throw RawFrameError(name + ": black level " + std::to_string(black.levels16[c]) +
                          " (16-bit scale) is outside 0..the largest code");
    levels.range[c] = largest - levels.offset[c];
  }
  return levels;
}

// One output row of RGB pixels from the two unpacked mosaic rows under it. A sample is stored
// kDecodedBlack16 above its black: read noise below black is kept, not clipped (a pixel's mean
// over many frames, or an area's over many pixels, stays unbiased in the dark). Only a sample
// further below black than the pedestal (about 20 times a Pi sensor's read noise) clips at 0.
void decodeCellRow(const std::vector<std::uint16_t> (&rows)[2],
                   const std::array<std::array<int, 2>, 2>& channels, const ChannelLevels& levels,
                   int widthPx, std::uint16_t* out) {
  const auto toStored = [](double value) {
    return static_cast<std::uint16_t>(std::clamp(value + kDecodedBlack16, 0.0, 65535.0) + 0.5);
  };
  for (int x = 0; x < widthPx; ++x) {
    double value[4] = {};
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int c = channels[dy][dx];
        // Multiplied before divided: the top code lands on 65535 exactly.
        value[c] = (rows[dy][2 * x + dx] - levels.offset[c]) * kDecodedSpan / levels.range[c];
      }
    out[3 * x + 0] = toStored(value[kR]);
    out[3 * x + 1] = toStored(0.5 * (value[kGr] + value[kGb]));
    out[3 * x + 2] = toStored(value[kB]);
  }
}

}  // namespace

Image decodeBayer(const BayerFrameView& raw, const BayerBlackLevels& black) {
  const std::string name = bayerFormatName(raw.format);
  checkBayerFrame(raw, name);
  const ChannelLevels levels = channelLevels(raw.format, black, name);
  const auto channels = cellChannels(raw.format.order);

  Image image;
  image.width = raw.widthPx / 2;
  image.height = raw.heightPx / 2;
  image.channels = 3;
  image.bitDepth = 16;
  image.samples.resize(std::size_t(image.width) * image.height * 3);
  std::vector<std::uint16_t> rows[2] = {std::vector<std::uint16_t>(std::size_t(raw.widthPx)),
                                        std::vector<std::uint16_t>(std::size_t(raw.widthPx))};
  for (int y = 0; y < image.height; ++y) {
    for (int dy = 0; dy < 2; ++dy)
      unpackRow(raw.format, raw.bytes.data() + std::size_t(2 * y + dy) * raw.strideBytes,
                raw.widthPx, rows[dy].data());
    decodeCellRow(rows, channels, levels, image.width,
                  &image.samples[std::size_t(y) * image.width * 3]);
  }
  return image;
}

std::vector<std::uint8_t> packBayer(const BayerFormat& format, int widthPx, int heightPx,
                                    std::span<const std::uint16_t> codes, std::size_t strideBytes) {
  if (!isValidFormat(format))
    throw HalError("packBayer: " + bayerFormatName(format) + " is not a valid format");
  if (widthPx <= 0 || heightPx <= 0 || codes.size() != std::size_t(widthPx) * heightPx)
    throw HalError("packBayer: " + std::to_string(codes.size()) + " codes for " +
                   std::to_string(widthPx) + " x " + std::to_string(heightPx));
  const std::size_t minimal = minimalBayerStrideBytes(format, widthPx);
  if (strideBytes == 0) strideBytes = minimal;
  if (strideBytes < minimal)
    throw HalError("packBayer: stride " + std::to_string(strideBytes) +
                   " below the minimal " + std::to_string(minimal));
  std::vector<std::uint8_t> bytes(strideBytes * std::size_t(heightPx), 0);
  for (int y = 0; y < heightPx; ++y) {
    std::uint8_t* row = bytes.data() + std::size_t(y) * strideBytes;
    const std::uint16_t* in = codes.data() + std::size_t(y) * widthPx;
    for (int x = 0; x < widthPx; ++x) {
      const unsigned code = in[x];
      if (format.packing == BayerPacking::Unpacked16) {
        row[2 * x] = static_cast<std::uint8_t>(code & 0xff);
        row[2 * x + 1] = static_cast<std::uint8_t>(code >> 8);
      } else if (format.bitDepth == 10) {
        std::uint8_t* group = row + 5 * (x / 4);
        const int k = x % 4;
        group[k] = static_cast<std::uint8_t>(code >> 2);
        group[4] = static_cast<std::uint8_t>(group[4] | ((code & 0x3) << (2 * k)));
      } else {
        std::uint8_t* group = row + 3 * (x / 2);
        const int k = x % 2;
        group[k] = static_cast<std::uint8_t>(code >> 4);
        group[2] = static_cast<std::uint8_t>(group[2] | ((code & 0xf) << (4 * k)));
      }
    }
  }
  return bytes;
}

}  // namespace slicecap::hal
