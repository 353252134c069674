// An image of raw integer samples (8- or 16-bit, 1-4 channels): PNG files and camera frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace slicecap {

/// \brief An image of raw integer samples, row-major, channels interleaved. 8-bit images hold
/// 0..255 in the 16-bit samples. Nothing is linearised: what the samples mean (sRGB-encoded or
/// linear) is the caller's convention (e.g. a recording's pixel encoding).
struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;  ///< 1 gray, 2 gray+alpha, 3 RGB, 4 RGBA
  int bitDepth = 8;  ///< 8 or 16
  std::vector<std::uint16_t> samples;

  std::uint16_t& at(int x, int y, int c) {
    return samples[(std::size_t(y) * width + x) * channels + c];
  }
  std::uint16_t at(int x, int y, int c) const {
    return samples[(std::size_t(y) * width + x) * channels + c];
  }
  /// \brief True when the shape is consistent (positive size, 1-4 channels, 8/16 bits, sample
  /// count).
  bool isValid() const;
};

}  // namespace slicecap
