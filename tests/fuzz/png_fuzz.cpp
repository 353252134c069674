// libFuzzer target: any bytes as a PNG frame. Each input is tried as it is and, when it differs,
// with every chunk's CRC made valid (libpng refuses a damaged critical chunk before looking at
// it, so mutated headers and palettes would otherwise never reach the reader's own checks).
// readPng either returns a consistent image, which writePng writes and readPng reads back
// unchanged, or throws io::IoError naming the file (the error a person sees); anything else is a
// bug (also an allocation the file cannot justify: libFuzzer's -malloc_limit_mb reports it).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

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

void readAndRoundTrip(const std::filesystem::path& file, const std::filesystem::path& again,
                      std::string_view bytes) {
  using namespace slicecap;
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
