// A frame's pixels as linear light: sRGB decoding, clipping, bilinear reads at sub-pixel positions.
#pragma once

#include <Eigen/Core>

#include "slicecap/core/rgb.hpp"
#include "slicecap/hal/frame.hpp"

namespace slicecap::capture {

/// \brief Reads a frame (8-bit sRGB or 16-bit linear, gray or RGB) as linear values, 1 = full
/// scale. Borrows the frame: it must outlive the view.
class LinearView {
 public:
  explicit LinearView(const hal::Frame& frame) : frame_(frame) {}

  /// \brief True when a bilinear read at `px` stays inside the image.
  bool inside(const Eigen::Vector2d& px) const {
    return px.x() >= 0 && px.y() >= 0 && px.x() <= frame_.image.width - 1.0 &&
           px.y() <= frame_.image.height - 1.0;
  }
  /// \brief Linear value of one sample; sets `*clipped` when it is at or above `clipFraction` of
  /// full scale.
  double linear(int x, int y, int c, double clipFraction, bool* clipped) const;
  /// \brief Bilinear linear RGB at a sub-pixel position inside the image (pixel centres at
  /// integer coordinates); sets `*clipped` when any of the four pixels is clipped.
  Rgb at(const Eigen::Vector2d& px, double clipFraction, bool* clipped) const;
  /// \brief The mean of the channels, never clipped.
  double gray(const Eigen::Vector2d& px) const {
    bool ignored = false;
    return at(px, 2.0, &ignored).mean();
  }

 private:
  const hal::Frame& frame_;
};

}  // namespace slicecap::capture
