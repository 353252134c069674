// The four measured subspaces of a capture (docs/method.md §3), the common first step of Methods A and B
// and of the methods built on them.
#pragma once

#include <string>
#include <vector>

#include "slicecap/core/slice.hpp"
#include "slicecap/recon/slice_sum.hpp"
#include "slicecap/recon/subspace.hpp"

namespace slicecap::recon {

/// \brief The subspaces at kMeasuredPairs, in that order: eq. 2-4 from each pair's axial and
/// diagonal slices, or eq. 5 from the diagonal one when `isotropic`. Throws ReconstructionError
/// that names `methodName` and every missing slice.
std::vector<Subspace> reconstructMeasuredSubspaces(const SliceSet& slices, bool isotropic,
                                                   TorusRule rule, const std::string& methodName);

}  // namespace slicecap::recon
