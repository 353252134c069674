// Camera buffers to Images: the pixel layouts the V4L2 and libcamera sources deliver, converted
// in one place so both sources (and their tests) agree on colours and strides.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string_view>

#include "slicecap/core/error.hpp"
#include "slicecap/core/image.hpp"
#include "slicecap/core/pixel_encoding.hpp"

namespace slicecap::hal {

/// \brief How a buffer's bytes are laid out, named by memory order (V4L2 and libcamera name the
/// same layouts differently: libcamera's RGB888 is B,G,R in memory).
enum class RawLayout {
  Yuyv,    ///< packed 4:2:2, Y0 U Y1 V (V4L2 YUYV, libcamera YUYV); BT.601 limited range
  Yuv420,  ///< planar 4:2:0, Y plane then U then V (V4L2 YUV420, libcamera YUV420)
  Rgb24,   ///< R,G,B bytes (V4L2 RGB24, libcamera BGR888)
  Bgr24,   ///< B,G,R bytes (V4L2 BGR24, libcamera RGB888)
  Bgrx32,  ///< B,G,R,X bytes (libcamera XRGB8888)
  Grey8,   ///< one byte per pixel (V4L2 GREY)
  Y16,     ///< 16-bit little-endian luminance, linear (V4L2 Y16)
};

/// \brief One frame's bytes as the device delivered them: the planes (one for packed layouts,
/// three for Yuv420: Y, U, V) and the stride of each plane in bytes.
struct RawFrameView {
  RawLayout layout = RawLayout::Yuyv;
  int widthPx = 0;
  int heightPx = 0;
  std::span<const std::uint8_t> planes[3];
  std::size_t strideBytes[3] = {0, 0, 0};
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
/// encodingOf(layout). Throws RawFrameError when a plane is too small for its stride and height.
Image toImage(const RawFrameView& raw);

/// \brief "YUYV", "YUV420", ... for messages and `--json` output.
std::string_view toString(RawLayout layout);

}  // namespace slicecap::hal
