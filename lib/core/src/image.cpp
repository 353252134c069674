// Image shape checks and the spelling of pixel encodings.
#include "slicecap/core/image.hpp"

#include "slicecap/core/pixel_encoding.hpp"

namespace slicecap {

bool Image::isValid() const {
  return width > 0 && height > 0 && channels >= 1 && channels <= 4 &&
         (bitDepth == 8 || bitDepth == 16) &&
         samples.size() == std::size_t(width) * height * channels;
}

std::string_view toString(PixelEncoding encoding) {
  return encoding == PixelEncoding::Srgb8 ? "srgb8" : "linear16";
}

std::optional<PixelEncoding> parsePixelEncoding(std::string_view text) {
  if (text == "srgb8") return PixelEncoding::Srgb8;
  if (text == "linear16") return PixelEncoding::Linear16;
  return std::nullopt;
}

int bitDepthOf(PixelEncoding encoding) {
  return encoding == PixelEncoding::Srgb8 ? 8 : 16;
}

}  // namespace slicecap
