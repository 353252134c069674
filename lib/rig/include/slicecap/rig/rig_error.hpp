// The error lib/rig throws for devices it cannot configure.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::rig {

/// \brief A configured device lib/rig cannot make (a file camera's recordings missing); the message
/// names the configured path.
class RigError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::rig
