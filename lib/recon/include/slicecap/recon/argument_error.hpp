// The error lib/recon throws for arguments it refuses.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::recon {

/// \brief Arguments lib/recon refuses (parameters out of range, coinciding RBF centres, a non-
/// finite sample, subspaces out of order): a caller's mistake. Unlike ReconstructionError
/// (errors.hpp), which says the slices cannot give a table and which callers catch to fall back or
/// to count a failed texel, it is not caught on the way.
class ReconArgumentError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::recon
