// The exception the reconstruction throws when its input cannot give a table.
#pragma once

#include <stdexcept>

#include "slicecap/core/error.hpp"

namespace slicecap::recon {

/// \brief Input that cannot be reconstructed (a missing slice, a slice without finite samples,
/// ...); the message names the slice.
class ReconstructionError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::recon
