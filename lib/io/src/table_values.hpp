// What a BRDF table may hold, checked by every table reader and writer of lib/io alike.
#pragma once

#include <optional>
#include <string>

#include "slicecap/core/abrdf.hpp"

namespace slicecap::io {

/// \brief The first value a BRDF table may not hold, described with its place: "non-finite value
/// at light 3, view 40, channel G" or "negative value -0.25 at light 3, view 40, channel G (a
/// BRDF is never negative)"; nothing when every value is finite and not negative (-0 is zero).
/// Every reconstruction clips at 0, so a negative value means a table from elsewhere that a
/// renderer would turn into negative light.
std::optional<std::string> firstInvalidValue(const Abrdf& table);

}  // namespace slicecap::io
