// Small helpers shared by the XML writers (MaterialX, Mitsuba): numbers and comment-safe text.
#pragma once

#include <cstdio>
#include <string>

#include "slicecap/core/rgb.hpp"

namespace slicecap::material_export::detail {

/// \brief A number with 6 significant digits, as both formats' parsers read it.
inline std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

/// \brief "r, g, b" (MaterialX color3) or "r g b"-style with `separator`.
inline std::string rgbText(const Rgb& c, const char* separator = ", ") {
  return num(c[0]) + separator + num(c[1]) + separator + num(c[2]);
}

/// \brief `text` made safe inside <!-- -->: "--" may not appear in an XML comment (XML 1.0 §2.5),
/// and a path could hold it.
inline std::string commentSafe(std::string text) {
  for (std::size_t at = text.find("--"); at != std::string::npos; at = text.find("--", at))
    text.replace(at, 2, "- -");
  if (!text.empty() && text.back() == '-') text.push_back(' ');
  return text;
}

}  // namespace slicecap::material_export::detail
