// The error lib/core throws for a value it refuses, so a caller can tell core's refusals apart.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap {

/// \brief A value lib/core refuses (a direction off the Bonn grid, a zero-length vector, a tone
/// curve that does not rise, a cell sample for a slice without samples); the message names it.
/// Modules that read such values from a file translate it into their own error, naming the file.
class CoreError : public Error {
 public:
  using Error::Error;
};

}  // namespace slicecap
