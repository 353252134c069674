// The exception every reader and writer throws; its message names the file (and line or field).
#pragma once

#include <stdexcept>

namespace slicecap::io {

/// \brief A file that cannot be read or written as asked; what() starts with the file's path.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace slicecap::io
