// An 8-bit sRGB picture to compose sheets in: fill, blit, text; converts to a PngImage.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "slicecap/io/png_image.hpp"

namespace slicecap::render {

/// \brief An 8-bit sRGB colour.
using Colour = std::array<std::uint8_t, 3>;

inline constexpr Colour kBlack{0, 0, 0};
inline constexpr Colour kWhite{255, 255, 255};
inline constexpr Colour kSheetBackground{24, 24, 24};
inline constexpr Colour kText{230, 230, 230};
inline constexpr Colour kDimText{150, 150, 150};

/// \brief A width x height RGB picture, row-major, filled with a colour. Drawing outside the
/// picture is clipped, never an error.
class Canvas {
 public:
  Canvas(int width, int height, Colour fill = kSheetBackground);

  int width() const { return width_; }
  int height() const { return height_; }
  Colour at(int x, int y) const;
  void set(int x, int y, Colour colour);
  void fillRect(int x, int y, int width, int height, Colour colour);
  /// \brief Copies `source` with its top-left corner at (x, y).
  void blit(const Canvas& source, int x, int y);
  /// \brief Draws text with the 5 x 7 bitmap font, top-left at (x, y), each font pixel `scale`
  /// pixels wide; returns the x after the text. Characters outside printable ASCII draw as '?'.
  int drawText(int x, int y, std::string_view text, Colour colour = kText, int scale = 1);

  /// \brief The picture as an 8-bit RGB PngImage (io::writePng writes it).
  io::PngImage toPng() const;

 private:
  int width_, height_;
  std::vector<Colour> pixels_;
};

/// \brief Width in pixels of `text` drawn at `scale` (6 pixels a character at scale 1).
int textWidth(std::string_view text, int scale = 1);
/// \brief Height of a line of text at `scale` (7 pixels at scale 1, without spacing).
inline int textHeight(int scale = 1) {
  return 7 * scale;
}

}  // namespace slicecap::render
