// A reconstructed BTF: for every light and view direction of the Bonn grid an N x N RGB image,
// half floats (BRDF, 1/sr).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "slicecap/core/abrdf.hpp"

namespace slicecap::btf {

/// \brief 81 x 81 images of N x N texels x RGB, stored as IEEE half floats (the EXR files'
/// type), light-major then view then texel rows: image (light, view) is contiguous, ready for
/// writing. Memory: 6561 x N^2 x 6 bytes (N = 128: 645 MB; N = 64: 161 MB).
class BtfTexture {
 public:
  /// \brief Zero images; throws BtfError unless 1 <= resolution <= 1024.
  explicit BtfTexture(int resolution);

  int resolution() const { return resolution_; }
  std::size_t texelCount() const { return std::size_t(resolution_) * resolution_; }

  /// \brief Stores one texel's table (values rounded to half). Thread-safe for distinct texels.
  void setTexel(std::size_t texel, const Abrdf& table);
  /// \brief Stores a row of texels' tables (one per column) at once: each image's row is written
  /// contiguously, where texel by texel every value would be a cache miss 6561 images apart.
  /// Thread-safe for distinct rows. Throws BtfError unless there is a table per
  /// column.
  void setRow(int row, std::span<const Abrdf> tables);
  /// \brief One texel's table, back in float.
  Abrdf texel(std::size_t texel) const;
  /// \brief One value as float.
  float value(int light, int view, std::size_t texel, int channel) const;
  /// \brief The half-float bits of image (light, view): N^2 x RGB, row-major.
  const std::uint16_t* image(int light, int view) const {
    return &halves_[(std::size_t(light) * Abrdf::kDirections + std::size_t(view)) * texelCount() *
                    3];
  }
  std::uint16_t* image(int light, int view) {
    return &halves_[(std::size_t(light) * Abrdf::kDirections + std::size_t(view)) * texelCount() *
                    3];
  }
  std::size_t memoryBytes() const { return halves_.size() * sizeof(std::uint16_t); }

 private:
  int resolution_;
  std::vector<std::uint16_t> halves_;
};

/// \brief The mean of all texels' tables (the texture's average ABRDF, for comparison with the
/// window-average capture).
Abrdf averageTable(const BtfTexture& texture);

}  // namespace slicecap::btf
