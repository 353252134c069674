// Whole numbers read from JSON, range-checked, without nlohmann's silent conversions.
#include "slicecap/io/json_numbers.hpp"

#include <utility>

namespace slicecap::io {

std::optional<std::int64_t> wholeNumberIn(const nlohmann::json& value, std::int64_t lo,
                                          std::int64_t hi) noexcept {
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (std::cmp_greater_equal(v, lo) && std::cmp_less_equal(v, hi))
      return static_cast<std::int64_t>(v);
    return std::nullopt;
  }
  if (value.is_number_integer()) {
    const auto v = value.get<std::int64_t>();
    if (v >= lo && v <= hi) return v;
  }
  return std::nullopt;
}

}  // namespace slicecap::io
