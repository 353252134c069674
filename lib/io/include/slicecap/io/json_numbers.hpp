// Whole numbers read from JSON without nlohmann's silent conversions.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>

namespace slicecap::io {

/// \brief `value` as a whole number in [lo, hi], or nullopt when it is anything else: not an
/// integer token (2.5, 1e300, "3", null) or out of the range. nlohmann's get<int>() of 1e300 is
/// undefined behaviour, of 2.5 quietly 2, and get<std::uint64_t>() of -1 wraps round, so a
/// reader that wants a count, an index or an angle in degrees checks here first and names the
/// field itself. Never throws.
std::optional<std::int64_t> wholeNumberIn(const nlohmann::json& value, std::int64_t lo,
                                          std::int64_t hi) noexcept;

}  // namespace slicecap::io
