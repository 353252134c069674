// The error a real camera source throws when it cannot be opened or set up.
#pragma once

#include <stdexcept>

#include "slicecap/core/error.hpp"

namespace slicecap::hal {

/// \brief A camera that cannot be opened, configured or started; what() names the device and
/// says what it answered. Per-frame failures are CaptureResult::Error values instead.
class CameraError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::hal
