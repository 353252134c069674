// The texture's texels: an N x N grid over the target's window, in the target plane.
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "slicecap/vision/target.hpp"

namespace slicecap::btf {

/// \brief N x N square texels covering the window. Texel (column i, row j) is an image pixel:
/// row 0 at the window's top edge (largest y), column 0 at its left edge (smallest x), so a
/// texture image shows the target as seen from above with x right and y up.
class TextureGrid {
 public:
  /// \brief Throws BtfError unless 1 <= resolution <= 1024 and the window is a
  /// rectangle.
  TextureGrid(int resolution, const vision::RectMm& window);

  int resolution() const { return resolution_; }
  std::size_t texelCount() const { return std::size_t(resolution_) * resolution_; }
  const vision::RectMm& window() const { return window_; }
  double texelWidthMm() const { return window_.widthMm() / resolution_; }
  double texelHeightMm() const { return window_.heightMm() / resolution_; }

  /// \brief The target point (z = 0, mm) at fractional texel coordinates: (i + 0.5, j + 0.5) is
  /// the centre of texel (i, j).
  Eigen::Vector3d pointMm(double column, double row) const {
    return {window_.xMinMm + column * texelWidthMm(), window_.yMaxMm - row * texelHeightMm(), 0.0};
  }
  Eigen::Vector3d texelCentreMm(int column, int row) const {
    return pointMm(column + 0.5, row + 0.5);
  }
  /// \brief Row-major index of a texel.
  std::size_t index(int column, int row) const {
    return std::size_t(row) * resolution_ + std::size_t(column);
  }

 private:
  int resolution_;
  vision::RectMm window_;
};

}  // namespace slicecap::btf
