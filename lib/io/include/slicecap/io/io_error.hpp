// The exception every reader and writer throws; its message names the file (and line or field).
#pragma once

#include <stdexcept>

#include "slicecap/core/error.hpp"

namespace slicecap::io {

/// \brief A file that cannot be read or written as asked; what() starts with the file's path.
class IoError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::io
