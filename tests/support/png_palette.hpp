// PNGs slicecap does not write but reads: 1-bit palette images, whose pixels libpng expands to
// 8-bit RGB(A), 24 or 32 times their stored size.
#pragma once

#include <png.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <vector>

namespace slicecap::test {

/// \brief Writes a width x height 1-bit palette PNG (black and white; with a tRNS chunk making
/// black transparent when `transparency`) whose pixels are all black: it compresses about 1000:1.
inline std::filesystem::path writeBlackPalettePng(const std::filesystem::path& path,
                                                  std::uint32_t width, std::uint32_t height,
                                                  bool transparency) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, 1, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_color palette[2] = {{0, 0, 0}, {255, 255, 255}};
  png_set_PLTE(png, info, palette, 2);
  png_byte alpha[1] = {0};
  if (transparency) png_set_tRNS(png, info, alpha, 1, nullptr);
  png_set_compression_level(png, 9);
  png_write_info(png, info);
  std::vector<png_byte> row((width + 7) / 8, 0);
  for (std::uint32_t y = 0; y < height; ++y)
    png_write_row(png, row.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
  return path;
}

}  // namespace slicecap::test
