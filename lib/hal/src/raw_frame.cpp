// Pixel layout conversions for the camera sources.
#include "slicecap/hal/raw_frame.hpp"

#include <algorithm>
#include <string>

namespace slicecap::hal {
namespace {

int planeCount(RawLayout layout) { return layout == RawLayout::Yuv420 ? 3 : 1; }

int planeHeight(RawLayout layout, int heightPx, int plane) {
  return layout == RawLayout::Yuv420 && plane > 0 ? (heightPx + 1) / 2 : heightPx;
}

std::uint16_t clampByte(int value) { return static_cast<std::uint16_t>(std::clamp(value, 0, 255)); }

/// BT.601 limited range (16-235 luma, 16-240 chroma), the default of UVC cameras and of
/// libcamera's YUV outputs, in 8.8 fixed point.
void yuvToRgb(int y, int u, int v, std::uint16_t* rgb) {
  const int c = 298 * (y - 16);
  const int d = u - 128;
  const int e = v - 128;
  rgb[0] = clampByte((c + 409 * e + 128) >> 8);
  rgb[1] = clampByte((c - 100 * d - 208 * e + 128) >> 8);
  rgb[2] = clampByte((c + 516 * d + 128) >> 8);
}

void checkPlanes(const RawFrameView& raw) {
  if (raw.widthPx <= 0 || raw.heightPx <= 0)
    throw RawFrameError("frame of " + std::to_string(raw.widthPx) + " x " +
                        std::to_string(raw.heightPx) + " pixels");
  for (int plane = 0; plane < planeCount(raw.layout); ++plane) {
    const std::size_t minimal = minimalStrideBytes(raw.layout, raw.widthPx, plane);
    const std::size_t stride = raw.strideBytes[plane];
    const std::string label = std::string(toString(raw.layout)) + " plane " + std::to_string(plane);
    if (stride < minimal)
      throw RawFrameError(label + ": stride " + std::to_string(stride) + " bytes, below the " +
                          std::to_string(minimal) + " a row needs");
    const int rows = planeHeight(raw.layout, raw.heightPx, plane);
    const std::size_t needed = stride * std::size_t(rows - 1) + minimal;
    if (raw.planes[plane].size() < needed)
      throw RawFrameError(label + ": " + std::to_string(raw.planes[plane].size()) +
                          " bytes, the frame needs " + std::to_string(needed));
  }
}

}  // namespace

PixelEncoding encodingOf(RawLayout layout) {
  return layout == RawLayout::Y16 ? PixelEncoding::Linear16 : PixelEncoding::Srgb8;
}

std::size_t minimalStrideBytes(RawLayout layout, int widthPx, int plane) {
  const auto width = static_cast<std::size_t>(widthPx);
  switch (layout) {
    case RawLayout::Yuyv: return 2 * ((width + 1) / 2) * 2;
    case RawLayout::Yuv420: return plane == 0 ? width : (width + 1) / 2;
    case RawLayout::Rgb24:
    case RawLayout::Bgr24: return 3 * width;
    case RawLayout::Bgrx32: return 4 * width;
    case RawLayout::Grey8: return width;
    case RawLayout::Y16: return 2 * width;
  }
  return 0;
}

std::string_view toString(RawLayout layout) {
  switch (layout) {
    case RawLayout::Yuyv: return "YUYV";
    case RawLayout::Yuv420: return "YUV420";
    case RawLayout::Rgb24: return "RGB24";
    case RawLayout::Bgr24: return "BGR24";
    case RawLayout::Bgrx32: return "BGRX32";
    case RawLayout::Grey8: return "GREY";
    case RawLayout::Y16: return "Y16";
  }
  return "unknown";
}

Image toImage(const RawFrameView& raw) {
  checkPlanes(raw);
  Image image;
  image.width = raw.widthPx;
  image.height = raw.heightPx;
  const bool gray = raw.layout == RawLayout::Grey8 || raw.layout == RawLayout::Y16;
  image.channels = gray ? 1 : 3;
  image.bitDepth = raw.layout == RawLayout::Y16 ? 16 : 8;
  image.samples.resize(std::size_t(image.width) * image.height * image.channels);
  for (int y = 0; y < raw.heightPx; ++y) {
    const std::uint8_t* row = raw.planes[0].data() + std::size_t(y) * raw.strideBytes[0];
    std::uint16_t* out = &image.samples[std::size_t(y) * image.width * image.channels];
    switch (raw.layout) {
      case RawLayout::Yuyv:
        for (int x = 0; x < raw.widthPx; ++x) {
          const std::uint8_t* pair = row + (x / 2) * 4;
          yuvToRgb(pair[(x % 2) * 2], pair[1], pair[3], out + 3 * x);
        }
        break;
      case RawLayout::Yuv420: {
        const std::uint8_t* uRow = raw.planes[1].data() + std::size_t(y / 2) * raw.strideBytes[1];
        const std::uint8_t* vRow = raw.planes[2].data() + std::size_t(y / 2) * raw.strideBytes[2];
        for (int x = 0; x < raw.widthPx; ++x) yuvToRgb(row[x], uRow[x / 2], vRow[x / 2], out + 3 * x);
        break;
      }
      case RawLayout::Rgb24:
        std::copy(row, row + 3 * std::size_t(raw.widthPx), out);
        break;
      case RawLayout::Bgr24:
      case RawLayout::Bgrx32: {
        const int step = raw.layout == RawLayout::Bgr24 ? 3 : 4;
        for (int x = 0; x < raw.widthPx; ++x) {
          out[3 * x + 0] = row[step * x + 2];
          out[3 * x + 1] = row[step * x + 1];
          out[3 * x + 2] = row[step * x + 0];
        }
        break;
      }
      case RawLayout::Grey8:
        std::copy(row, row + raw.widthPx, out);
        break;
      case RawLayout::Y16:
        for (int x = 0; x < raw.widthPx; ++x)
          out[x] = static_cast<std::uint16_t>(row[2 * x] | (row[2 * x + 1] << 8));
        break;
    }
  }
  return image;
}

}  // namespace slicecap::hal
