// Linear reads of 8-bit frames (through a code table) and 16-bit linear frames.
#include "slicecap/capture/linear_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace slicecap::capture {

CodeTable::CodeTable(const ToneCurve& curve) : name_(curve.name()) {
  for (int i = 0; i < 256; ++i) linear_[i] = curve.decode(i / 255.0);
}

const CodeTable& CodeTable::srgb() {
  static const CodeTable table = [] {
    CodeTable t;
    t.name_ = "srgb";
    for (int i = 0; i < 256; ++i) {
      const double v = i / 255.0;
      t.linear_[i] = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    }
    return t;
  }();
  return table;
}

double LinearView::linear(int x, int y, int c, double clipFraction, bool* clipped) const {
  const Image& im = frame_.image;
  const int channel = im.channels >= 3 ? c : 0;
  const std::uint16_t raw = im.at(x, y, channel);
  if (frame_.encoding == PixelEncoding::Srgb8) {
    if (raw >= clipFraction * 255.0) *clipped = true;
    return codes_[raw];
  }
  if (raw >= clipFraction * 65535.0) *clipped = true;
  return hal::linear16Value(raw, frame_.black16);
}

Rgb LinearView::at(const Eigen::Vector2d& px, double clipFraction, bool* clipped) const {
  const int x0 = std::min(static_cast<int>(px.x()), frame_.image.width - 2);
  const int y0 = std::min(static_cast<int>(px.y()), frame_.image.height - 2);
  const double fx = px.x() - x0, fy = px.y() - y0;
  Rgb value;
  for (int c = 0; c < 3; ++c) {
    const double top = (1 - fx) * linear(x0, y0, c, clipFraction, clipped) +
                       fx * linear(x0 + 1, y0, c, clipFraction, clipped);
    const double bottom = (1 - fx) * linear(x0, y0 + 1, c, clipFraction, clipped) +
                          fx * linear(x0 + 1, y0 + 1, c, clipFraction, clipped);
    value[c] = (1 - fy) * top + fy * bottom;
  }
  return value;
}

}  // namespace slicecap::capture
