// The exception the reconstruction throws when its input cannot give a table.
#pragma once

#include <stdexcept>

namespace slicecap::recon {

/// \brief Input that cannot be reconstructed (a missing slice, a slice without finite samples,
/// ...); the message names the slice.
class ReconstructionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace slicecap::recon
