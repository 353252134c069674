// The embedded 5 x 7 bitmap font of printable ASCII (private to the render module).
#pragma once

#include <array>
#include <cstdint>

namespace slicecap::render {

/// \brief Five columns, left to right; bit k of a column is row k from the top.
const std::array<std::uint8_t, 5>& glyphOf(char c);

}  // namespace slicecap::render
