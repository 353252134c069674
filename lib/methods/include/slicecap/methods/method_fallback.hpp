// A session that lacks a measured slice: which, the command that sweeps it, and the prior instead.
#pragma once

#include <string>
#include <vector>

#include "slicecap/methods/methods.hpp"

namespace slicecap::methods {

/// \brief The measured slices (axial and diagonal at 30/30, 30/75, 75/30, 75/75; the diagonal
/// ones only when `isotropic`) that `slices` has no sample of, in that order.
std::vector<SliceId> missingMeasuredSlices(const SliceSet& slices, bool isotropic);

/// \brief The command that sweeps `slice` in the current session, e.g.
/// "slicecap sweep start diagonal 75 75".
std::string sweepCommand(const SliceId& slice);

/// \brief `method` on `slices`; when the method needs every measured slice
/// (SliceSubset::EveryMeasuredSlice) and some are missing, the prior, which reads any subset,
/// with a warning naming each missing slice and the command that sweeps it. Throws what the
/// method throws, and a recon::ReconstructionError naming the missing slices and their commands
/// when the prior fails too or when every axial slice is missing and every diagonal one there (an
/// isotropic capture without --isotropic: said, not hidden by the prior).
MethodRun runMethodOrPrior(const Method& method, const SliceSet& slices,
                           const MethodOptions& options);

}  // namespace slicecap::methods
