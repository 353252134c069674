// The error lib/cli throws for a command's input it cannot use.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::cli {

/// \brief A command's input that exists but cannot be used (a folder without tables, a table
/// without a positive value); exit code 1 as any failure. Bad usage of the command line is
/// slicecap::UsageError (exit 2).
class CommandError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::cli
