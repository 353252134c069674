// The exception the method registry throws for a method name or option spec it cannot read.
#pragma once

#include <stdexcept>

#include "slicecap/core/error.hpp"

namespace slicecap::methods {

/// \brief A method name that is not in the registry, or an RBF spec (`--rbf`) with an unknown key
/// or a value out of range; the message names the input and what would be valid. A method that
/// cannot reconstruct its samples throws the reconstruction's own errors (e.g.
/// recon::ReconstructionError), not this.
class MethodError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::methods
