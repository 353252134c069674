// The error lib/btf throws for textures it cannot make.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::btf {

/// \brief A texture lib/btf cannot capture, store or reconstruct from its arguments (a resolution
/// out of range, a frame of another size, recordings that do not belong together); the message
/// names them. A store that cannot be read or written is io::IoError.
class BtfError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::btf
