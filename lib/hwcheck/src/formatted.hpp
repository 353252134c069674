// printf-style text for the check's findings (numbers with their units in the pattern).
#pragma once

#include <cstdio>
#include <string>

namespace slicecap::hwcheck {

/// \brief `pattern` filled with `values` by snprintf, cut at 200 characters.
template <typename... Values>
std::string formatted(const char* pattern, Values... values) {
  char text[200];
  std::snprintf(text, sizeof text, pattern, values...);
  return text;
}

}  // namespace slicecap::hwcheck
