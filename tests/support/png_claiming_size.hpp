// A small, valid PNG whose header claims another size: what a decompression bomb or a damaged
// frame looks like to a reader.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>

#include "slicecap/io/journal.hpp"
#include "slicecap/io/png_image.hpp"

namespace slicecap::test {

/// \brief Writes a 4 x 3 RGB PNG to `path`, then rewrites its IHDR to claim width x height with
/// a valid CRC (so libpng accepts the header itself). Returns `path`.
inline std::filesystem::path writePngClaimingSize(const std::filesystem::path& path,
                                                  std::uint32_t width, std::uint32_t height) {
  io::writePng(path, Image{4, 3, 3, 8, std::vector<std::uint16_t>(4 * 3 * 3, 100)});
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // Signature (8), IHDR length (4), "IHDR" (4), width and height big-endian (16, 20), depth,
  // colour type, compression, filter, interlace, then the CRC of type and data (29).
  const auto putBigEndian = [&](std::size_t at, std::uint32_t value) {
    for (int i = 0; i < 4; ++i)
      bytes[at + i] = static_cast<char>((value >> (24 - 8 * i)) & 0xff);
  };
  putBigEndian(16, width);
  putBigEndian(20, height);
  putBigEndian(29, io::crc32(std::string_view(bytes).substr(12, 17)));
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  return path;
}

}  // namespace slicecap::test
