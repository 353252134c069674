// The error lib/render throws for a picture it cannot draw.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::render {

/// \brief A picture lib/render cannot draw (a size below its minimum, a table without a positive
/// value to scale by, a panel without a table); the message names it.
class RenderError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::render
