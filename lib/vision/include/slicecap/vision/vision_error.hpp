// The error lib/vision throws for a target or camera model it refuses.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::vision {

/// \brief A target's parameters, a raster or a camera model's scaling that lib/vision refuses; the
/// message names the value. (A tag id outside tag36h11 is a programming error: std::out_of_range.)
class VisionError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::vision
