// What a BRDF table may hold.
#include "table_values.hpp"

#include <cmath>
#include <cstdio>

namespace slicecap::io {

std::optional<std::string> firstInvalidValue(const Abrdf& table) {
  constexpr const char* kChannels[3] = {"R", "G", "B"};
  const auto values = table.values();
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float v = values[i];
    if (std::isfinite(v) && !(v < 0.0f)) continue;
    const std::size_t pixel = i / 3;
    const std::string where = "at light " + std::to_string(pixel / Abrdf::kDirections) + ", view " +
                              std::to_string(pixel % Abrdf::kDirections) + ", channel " +
                              kChannels[i % 3];
    if (!std::isfinite(v)) return "non-finite value " + where;
    char number[32];
    std::snprintf(number, sizeof number, "%g", double(v));
    return "negative value " + std::string(number) + " " + where + " (a BRDF is never negative)";
  }
  return std::nullopt;
}

}  // namespace slicecap::io
