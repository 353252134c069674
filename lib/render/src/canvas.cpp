// Canvas drawing with clipping, and the conversion to a PNG image.
#include "slicecap/render/canvas.hpp"

#include <algorithm>
#include <stdexcept>

#include "bitmap_font.hpp"
#include "slicecap/render/render_error.hpp"

namespace slicecap::render {

Canvas::Canvas(int width, int height, Colour fill)
    : width_(width),
      height_(height),
      pixels_(std::size_t(std::max(width, 0)) * std::size_t(std::max(height, 0)), fill) {
  if (width <= 0 || height <= 0) throw RenderError("canvas size must be positive");
}

Colour Canvas::at(int x, int y) const {
  return pixels_.at(std::size_t(y) * width_ + x);
}

void Canvas::set(int x, int y, Colour colour) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  pixels_[std::size_t(y) * width_ + x] = colour;
}

void Canvas::fillRect(int x, int y, int width, int height, Colour colour) {
  for (int row = std::max(y, 0); row < std::min(y + height, height_); ++row) {
    for (int column = std::max(x, 0); column < std::min(x + width, width_); ++column)
      pixels_[std::size_t(row) * width_ + column] = colour;
  }
}

void Canvas::blit(const Canvas& source, int x, int y) {
  for (int row = 0; row < source.height_; ++row) {
    for (int column = 0; column < source.width_; ++column)
      set(x + column, y + row, source.pixels_[std::size_t(row) * source.width_ + column]);
  }
}

int Canvas::drawText(int x, int y, std::string_view text, Colour colour, int scale) {
  for (char c : text) {
    const std::array<std::uint8_t, 5>& glyph = glyphOf(c);
    for (int column = 0; column < 5; ++column) {
      for (int row = 0; row < 7; ++row) {
        if (glyph[column] & (1u << row))
          fillRect(x + column * scale, y + row * scale, scale, scale, colour);
      }
    }
    x += 6 * scale;
  }
  return x;
}

io::PngImage Canvas::toPng() const {
  io::PngImage image;
  image.width = width_;
  image.height = height_;
  image.channels = 3;
  image.bitDepth = 8;
  image.samples.reserve(pixels_.size() * 3);
  for (const Colour& p : pixels_)
    image.samples.insert(image.samples.end(), p.begin(), p.end());
  return image;
}

int textWidth(std::string_view text, int scale) {
  return text.empty() ? 0 : (6 * int(text.size()) - 1) * scale;
}

}  // namespace slicecap::render
