// libFuzzer target: any bytes as a PNG frame. Each input is tried as it is and, when it differs,
// with every chunk's CRC made valid (libpng refuses a damaged critical chunk before looking at
// it, so mutated headers and palettes would otherwise never reach the reader's own checks).
// readPng either returns a consistent image, which writePng writes and readPng reads back
// unchanged, or throws io::IoError naming the file (the error a person sees); anything else is a
// bug (also an allocation the file cannot justify: libFuzzer's -malloc_limit_mb reports it). A
// valid image as large as its header says is not read: a 49 kB 1-bit palette image can hold
// 20000 x 20000 pixels, 3.6 GB once read, and reading it takes that much.
#include <png.h>

#include <csetjmp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_file.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"
#include "slicecap/io/png_image.hpp"

namespace {

// The chunks after the 8-byte signature (length, type, data, CRC) with their CRCs recomputed;
// a last chunk cut short stays as it is.
std::string withValidChunkCrcs(std::string_view png) {
  std::string out(png);
  std::size_t at = 8;
  while (at + 12 <= out.size()) {
    const auto byte = [&](std::size_t i) { return std::uint32_t(std::uint8_t(out[i])); };
    const std::uint32_t length =
        byte(at) << 24 | byte(at + 1) << 16 | byte(at + 2) << 8 | byte(at + 3);
    if (length > out.size() - at - 12) break;
    const std::uint32_t crc = slicecap::io::crc32(std::string_view(out).substr(at + 4, 4 + length));
    for (int i = 0; i < 4; ++i)
      out[at + 8 + length + i] = static_cast<char>(crc >> (24 - 8 * i));
    at += 12 + length;
  }
  return out;
}

// Whether libpng decodes the PNG whole and it takes more than 1 GB to hold as readPng holds it
// (libpng's rows expanded to 8-bit RGB(A), and 16-bit samples).
bool validAndHuge(std::string_view bytes) {
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0)
    return false;
  struct Reader {
    std::string_view rest;
  } reader{bytes};
  png_structp png = png_create_read_struct(
      PNG_LIBPNG_VER_STRING, nullptr, [](png_structp p, png_const_charp) { png_longjmp(p, 1); },
      [](png_structp, png_const_charp) {});
  png_infop info = png_create_info_struct(png);
  png_set_read_fn(png, &reader, [](png_structp p, png_bytep out, png_size_t length) {
    auto* r = static_cast<Reader*>(png_get_io_ptr(p));
    if (length > r->rest.size()) png_error(p, "truncated");
    std::memcpy(out, r->rest.data(), length);
    r->rest.remove_prefix(length);
  });
  std::vector<png_byte> row;
  volatile bool huge = false, whole = false;  // set between setjmp and a longjmp
  if (setjmp(png_jmpbuf(png)) == 0) {
    png_read_info(png, info);
    if (png_get_color_type(png, info) == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (png_get_color_type(png, info) == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(png, info) < 8)
      png_set_expand_gray_1_2_4_to_8(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
    const int passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    const std::uint64_t height = png_get_image_height(png, info);
    const std::uint64_t samples =
        std::uint64_t(png_get_image_width(png, info)) * height * png_get_channels(png, info);
    huge = std::uint64_t(png_get_rowbytes(png, info)) * height + 2 * samples > (1ull << 30);
    if (huge) {
      row.resize(png_get_rowbytes(png, info));  // at most 65535 x 8 bytes, as readPng checks
      for (int pass = 0; pass < passes; ++pass)
        for (std::uint64_t y = 0; y < height; ++y)
          png_read_row(png, row.data(), nullptr);
      png_read_end(png, nullptr);
      whole = true;
    }
  }
  png_destroy_read_struct(&png, &info, nullptr);
  return huge && whole;
}

void readAndRoundTrip(const std::filesystem::path& file, const std::filesystem::path& again,
                      std::string_view bytes) {
  using namespace slicecap;
  if (validAndHuge(bytes)) return;
  fuzz::writeBytes(file, bytes);
  io::PngImage image;
  try {
    image = io::readPng(file);
  } catch (const io::IoError&) {
    return;
  }
  if (!image.isValid()) std::abort();
  // The round trip costs an encode; small images are where the fuzzer spends its time anyway.
  if (image.samples.size() <= (std::size_t(1) << 16)) {
    io::writePng(again, image);
    if (io::readPng(again).samples != image.samples) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slicecap;
  static const std::filesystem::path dir = fuzz::scratchDir("png");
  static const std::filesystem::path file = dir / "frame.png", again = dir / "again.png";
  const std::string_view input = fuzz::asText(data, size);
  readAndRoundTrip(file, again, input);
  const std::string sealed = withValidChunkCrcs(input);
  if (sealed != input) readAndRoundTrip(file, again, sealed);
  return 0;
}
