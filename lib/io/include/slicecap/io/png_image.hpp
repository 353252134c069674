// PNG files as raw samples: 8- or 16-bit, gray, gray+alpha, RGB or RGBA, no colour conversion.
#pragma once

#include <filesystem>

#include "slicecap/core/image.hpp"

namespace slicecap::io {

/// \brief The image a PNG holds (slicecap::Image: raw 8- or 16-bit samples, no colour conversion).
using PngImage = Image;

/// \brief The largest width or height readPng accepts: well beyond any camera, and it bounds what
/// a header can make the reader allocate.
inline constexpr unsigned kMaxPngSidePx = 65535;

/// \brief Reads a PNG; palette and low-bit-depth images are expanded to 8 bits. Throws IoError
/// naming the path (missing, a directory, not a PNG, truncated, corrupt: libpng's own message is
/// included; a header claiming a side above kMaxPngSidePx, or more pixel data than the file's size
/// can inflate to, is corrupt and refused before anything is allocated for it; pixels that expand,
/// e.g. 1-bit palette indices to RGBA, beyond what the file could hold unexpanded are decoded once
/// without being kept before memory is allocated for them; an image larger than the memory that
/// can be allocated is named too).
PngImage readPng(const std::filesystem::path& path);

/// \brief Writes a PNG of the image's depth and channels. Throws IoError naming the path, also for
/// an invalid image or a sample above 255 in an 8-bit image. A positive `pixelsPerMetre` is stored
/// in the pHYs chunk, so viewers print the image at true scale (the printable target). A failure
/// leaves an old file at `path` as it was (written through a temporary).
void writePng(const std::filesystem::path& path, const PngImage& image, double pixelsPerMetre = 0.0);

}  // namespace slicecap::io
