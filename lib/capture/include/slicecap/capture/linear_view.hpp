// A frame's pixels as linear light: 8-bit decoding (sRGB or a camera's measured tone curve),
// clipping, bilinear reads at sub-pixel positions.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>

#include "slicecap/core/rgb.hpp"
#include "slicecap/core/tone_curve.hpp"
#include "slicecap/hal/frame.hpp"

namespace slicecap::capture {

/// \brief The linear value (1 = full scale) of every 8-bit code under one tone curve, computed
/// once: what LinearView reads 8-bit frames through.
class CodeTable {
 public:
  /// \brief The table of `curve` (its decode() at code / 255).
  explicit CodeTable(const ToneCurve& curve);
  /// \brief The sRGB transfer curve, by its formula (IEC 61966-2-1): the default decoding.
  static const CodeTable& srgb();

  double operator[](std::uint16_t code) const { return linear_[code < 256 ? code : 255]; }
  /// \brief "srgb", or the curve's name ("measured", "linear", ...).
  const std::string& name() const { return name_; }

 private:
  CodeTable() = default;
  std::string name_;
  std::array<double, 256> linear_{};
};

/// \brief Reads a frame (8-bit through a tone curve, or 16-bit linear above the frame's black16;
/// gray or RGB) as linear values, 1 = full scale; a RAW frame's read noise below black reads
/// negative. Borrows the frame and the table: both must outlive the view.
class LinearView {
 public:
  /// \brief 8-bit samples decoded as sRGB.
  explicit LinearView(const hal::Frame& frame) : LinearView(frame, CodeTable::srgb()) {}
  /// \brief 8-bit samples decoded through `codes` (16-bit ones are linear whatever it says).
  LinearView(const hal::Frame& frame, const CodeTable& codes) : frame_(frame), codes_(codes) {}

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
  const CodeTable& codes_;
};

}  // namespace slicecap::capture
