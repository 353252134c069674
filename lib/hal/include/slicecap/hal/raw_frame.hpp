// Camera buffers to Images: the pixel layouts the V4L2 and libcamera sources deliver, converted
// in one place so both sources (and their tests) agree on colours and strides.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "slicecap/core/error.hpp"
#include "slicecap/core/image.hpp"
#include "slicecap/core/pixel_encoding.hpp"

namespace slicecap::hal {

/// \brief How a buffer's bytes are laid out, named by memory order (V4L2 and libcamera name the
/// same layouts differently: libcamera's RGB888 is B,G,R in memory).
enum class RawLayout {
  Yuyv,    ///< packed 4:2:2, Y0 U Y1 V (V4L2 YUYV, libcamera YUYV); decoded by its YuvEncoding
  Yuv420,  ///< planar 4:2:0, Y plane then U then V (V4L2 YUV420, libcamera YUV420); likewise
  Rgb24,   ///< R,G,B bytes (V4L2 RGB24, libcamera BGR888)
  Bgr24,   ///< B,G,R bytes (V4L2 BGR24, libcamera RGB888)
  Bgrx32,  ///< B,G,R,X bytes (libcamera XRGB8888)
  Grey8,   ///< one byte per pixel (V4L2 GREY)
  Y16,     ///< 16-bit little-endian luminance, linear (V4L2 Y16)
};

/// \brief The YCbCr matrix of a YUV stream: the luma coefficients (Kr, Kb) of ITU-R BT.601
/// (0.299, 0.114; sYCC and SMPTE 170M), BT.709 (0.2126, 0.0722) or BT.2020 (0.2627, 0.0593,
/// non-constant luminance).
enum class YcbcrMatrix { Rec601, Rec709, Rec2020 };

/// \brief A YUV stream's quantisation at 8 bits: Limited, Y' = 16 + 219 E'Y and
/// Cb, Cr = 128 + 224 E'Pb,Pr (BT.601/709/2020); Full, Y' = 255 E'Y and Cb, Cr = 128 + 255
/// E'Pb,Pr (sYCC, IEC 61966-2-1 Amd. 1, and JFIF, ITU-T T.871).
enum class YuvRange { Limited, Full };

/// \brief How a YUV stream's bytes encode R'G'B': its matrix and range, as the camera reports
/// them (libcamera's StreamConfiguration::colorSpace, V4L2's v4l2_pix_format ycbcr_enc and
/// quantization).
struct YuvEncoding {
  YcbcrMatrix matrix = YcbcrMatrix::Rec601;
  YuvRange range = YuvRange::Limited;
  friend bool operator==(const YuvEncoding&, const YuvEncoding&) = default;
};

/// \brief "Rec.709 limited range", "Rec.601 full range", ... for messages.
std::string toString(YuvEncoding encoding);

/// \brief One frame's bytes as the device delivered them: the planes (one for packed layouts,
/// three for Yuv420: Y, U, V) and the stride of each plane in bytes.
struct RawFrameView {
  RawLayout layout = RawLayout::Yuyv;
  int widthPx = 0;
  int heightPx = 0;
  std::span<const std::uint8_t> planes[3];
  std::size_t strideBytes[3] = {0, 0, 0};
  /// The YUV layouts' matrix and range: required for them (toImage refuses a YUV frame without
  /// it rather than guess), ignored for the others.
  std::optional<YuvEncoding> yuv{};
};

/// \brief A buffer whose size or strides do not fit its layout (a driver bug or a truncated
/// buffer); what() says which plane and by how much.
class RawFrameError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief The encoding a layout's samples carry: Y16 is linear 16-bit, everything else 8-bit
/// gamma-encoded (taken as sRGB).
PixelEncoding encodingOf(RawLayout layout);

/// \brief The bytes a plane needs for `widthPx` x `heightPx` with the layout's minimal stride.
std::size_t minimalStrideBytes(RawLayout layout, int widthPx, int plane);

/// \brief Converts to an RGB Image (3 channels; 1 channel for Grey8 and Y16), 8-bit or 16-bit as
/// encodingOf(layout); YUV through the frame's `yuv` matrix and range (R'G'B' rounded and
/// clipped to 0..255). Throws RawFrameError when a plane is too small for its stride and height,
/// or a YUV frame comes without its `yuv`.
Image toImage(const RawFrameView& raw);

/// \brief Whether `layout` is one of the YUV layouts (which need a YuvEncoding).
bool isYuv(RawLayout layout);

/// \brief "YUYV", "YUV420", ... for messages and `--json` output.
std::string_view toString(RawLayout layout);

}  // namespace slicecap::hal
