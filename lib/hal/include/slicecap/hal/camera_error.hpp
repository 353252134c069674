// The error a real camera source throws when it cannot be opened or set up.
#pragma once

#include <stdexcept>

namespace slicecap::hal {

/// \brief A camera that cannot be opened, configured or started; what() names the device and
/// says what it answered. Per-frame failures are CaptureResult::Error values instead.
class CameraError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace slicecap::hal
