// How a frame's integer samples relate to linear light: 8-bit sRGB or 16-bit linear.
#pragma once

#include <optional>
#include <string_view>

namespace slicecap {

/// \brief Srgb8: 8-bit samples, sRGB transfer curve (what a person looks at). Linear16: 16-bit
/// samples proportional to the sensor's linear signal, 65535 = full scale (what measures best).
enum class PixelEncoding { Srgb8, Linear16 };

/// \brief "srgb8" or "linear16" (the spelling of recording.json and the command line).
std::string_view toString(PixelEncoding encoding);
/// \brief The encoding spelled exactly "srgb8" or "linear16", or nullopt.
std::optional<PixelEncoding> parsePixelEncoding(std::string_view text);
/// \brief 8 or 16.
int bitDepthOf(PixelEncoding encoding);

}  // namespace slicecap
