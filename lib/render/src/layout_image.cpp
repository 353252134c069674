// Layout and difference pictures on the paper's 8-bit encoding.
#include "slicecap/render/layout_image.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/render/render_error.hpp"

namespace slicecap::render {
namespace {

constexpr Colour kRingLine{72, 72, 72};

// Pixel offset of an entry: its index in whole entries plus one line per ring boundary before it.
int offsetOf(int directionIndex, int pixelsPerEntry) {
  return directionIndex * pixelsPerEntry + bonn::ringOfIndex(directionIndex);
}

void checkArguments(double referenceMax, int pixelsPerEntry) {
  if (pixelsPerEntry < 1) throw RenderError("layout: pixels per entry must be >= 1");
  if (!(referenceMax > 0.0)) throw RenderError("layout: reference maximum must be > 0");
}

// Draws every entry with colour(light, view) and the ring lines between the blocks.
template <typename ColourOf>
Canvas drawLayout(int pixelsPerEntry, ColourOf colourOf) {
  const int side = layoutSide(pixelsPerEntry);
  Canvas canvas(side, side, kRingLine);
  for (int l = 0; l < Abrdf::kDirections; ++l) {
    for (int v = 0; v < Abrdf::kDirections; ++v) {
      canvas.fillRect(offsetOf(v, pixelsPerEntry), offsetOf(l, pixelsPerEntry), pixelsPerEntry,
                      pixelsPerEntry, colourOf(l, v));
    }
  }
  return canvas;
}

}  // namespace

int layoutSide(int pixelsPerEntry) {
  return Abrdf::kDirections * pixelsPerEntry + bonn::kRingCount - 1;
}

Canvas layoutImage(const Abrdf& table, double referenceMax, int pixelsPerEntry) {
  checkArguments(referenceMax, pixelsPerEntry);
  const auto encoded = eval::encodePaper8Bit(table, referenceMax);
  return drawLayout(pixelsPerEntry, [&](int l, int v) {
    const std::size_t o = (std::size_t(l) * Abrdf::kDirections + v) * 3;
    return Colour{encoded[o], encoded[o + 1], encoded[o + 2]};
  });
}

Canvas differenceImage(const Abrdf& reference, const Abrdf& test, double referenceMax, int gain,
                       int pixelsPerEntry) {
  checkArguments(referenceMax, pixelsPerEntry);
  const auto ref = eval::encodePaper8Bit(reference, referenceMax);
  const auto rec = eval::encodePaper8Bit(test, referenceMax);
  return drawLayout(pixelsPerEntry, [&](int l, int v) {
    const std::size_t o = (std::size_t(l) * Abrdf::kDirections + v) * 3;
    Colour c{};
    for (std::size_t k = 0; k < 3; ++k)
      c[k] = std::uint8_t(std::min(255, std::abs(int(ref[o + k]) - int(rec[o + k])) * gain));
    return c;
  });
}

}  // namespace slicecap::render
