// The error lib/hwcheck throws for a check it cannot finish.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::hwcheck {

/// \brief A hardware check that cannot finish (the camera stops delivering frames, refuses an
/// exposure lock) or a configuration snippet it cannot write; the message names the camera or file.
class HardwareCheckError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::hwcheck
