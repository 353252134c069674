// Pixel layout conversions for the camera sources.
#include "slicecap/hal/raw_frame.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace slicecap::hal {
namespace {

int planeCount(RawLayout layout) { return layout == RawLayout::Yuv420 ? 3 : 1; }

int planeHeight(RawLayout layout, int heightPx, int plane) {
  return layout == RawLayout::Yuv420 && plane > 0 ? (heightPx + 1) / 2 : heightPx;
}

std::uint16_t clampByte(int value) { return static_cast<std::uint16_t>(std::clamp(value, 0, 255)); }

/// Y'CbCr to R'G'B' by the inverse of the matrix's equations (E'Y = Kr R' + Kg G' + Kb B',
/// E'Pb = (B' - E'Y) / (2 (1 - Kb)), E'Pr = (R' - E'Y) / (2 (1 - Kr))), the range's offsets and
/// scales folded in, in 16.16 fixed point (within 1/256 of a code of the exact value).
class YuvDecoder {
 public:
  explicit YuvDecoder(YuvEncoding encoding) {
    const auto [kr, kb] = lumaCoefficients(encoding.matrix);
    const double kg = 1.0 - kr - kb;
    const bool limited = encoding.range == YuvRange::Limited;
    yOffset_ = limited ? 16 : 0;
    const double yScale = limited ? 255.0 / 219.0 : 1.0;
    const double cScale = limited ? 255.0 / 224.0 : 1.0;
    const auto fixed = [](double v) { return static_cast<int>(std::lround(v * 65536.0)); };
    y_ = fixed(yScale);
    rv_ = fixed(cScale * 2.0 * (1.0 - kr));
    bu_ = fixed(cScale * 2.0 * (1.0 - kb));
    gu_ = fixed(cScale * 2.0 * (1.0 - kb) * kb / kg);
    gv_ = fixed(cScale * 2.0 * (1.0 - kr) * kr / kg);
  }

  void operator()(int y, int u, int v, std::uint16_t* rgb) const {
    const int luma = y_ * (y - yOffset_) + 32768;  // + one half: rounded, not truncated
    const int d = u - 128, e = v - 128;
    rgb[0] = clampByte((luma + rv_ * e) >> 16);
    rgb[1] = clampByte((luma - gu_ * d - gv_ * e) >> 16);
    rgb[2] = clampByte((luma + bu_ * d) >> 16);
  }

 private:
  static std::pair<double, double> lumaCoefficients(YcbcrMatrix matrix) {
    switch (matrix) {
      case YcbcrMatrix::Rec601: return {0.299, 0.114};
      case YcbcrMatrix::Rec709: return {0.2126, 0.0722};
      case YcbcrMatrix::Rec2020: return {0.2627, 0.0593};
    }
    return {0.299, 0.114};
  }
  int yOffset_ = 16, y_ = 0, rv_ = 0, bu_ = 0, gu_ = 0, gv_ = 0;
};

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

std::string toString(YuvEncoding encoding) {
  const char* matrix = encoding.matrix == YcbcrMatrix::Rec601   ? "Rec.601"
                       : encoding.matrix == YcbcrMatrix::Rec709 ? "Rec.709"
                                                                : "Rec.2020";
  return std::string(matrix) + (encoding.range == YuvRange::Full ? " full range" : " limited range");
}

bool isYuv(RawLayout layout) { return layout == RawLayout::Yuyv || layout == RawLayout::Yuv420; }

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
  if (isYuv(raw.layout) && !raw.yuv)
    throw RawFrameError(std::string(toString(raw.layout)) +
                        " frame without its YCbCr matrix and range: not decoded by a guess");
  const YuvDecoder yuvToRgb(raw.yuv.value_or(YuvEncoding{}));
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
