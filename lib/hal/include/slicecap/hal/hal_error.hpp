// The error lib/hal throws for device models and frames it cannot make.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::hal {

/// \brief A frame, LED timeline or camera model lib/hal cannot make from its arguments, or a system
/// call the camera model needs failing; the message names them. A device's own failure is
/// CameraError, GpioError or DeviceError; a call out of order is std::logic_error (a programming
/// error).
class HalError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::hal
