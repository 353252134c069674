// RBF interpolation over samples wherever they lie: the uniform baseline's reconstruction
// (docs/method.md §6.3), with Method A's kernel and parameterisation.
#pragma once

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/recon/onion.hpp"
#include "slicecap/recon/rbf_interpolant.hpp"

namespace slicecap::recon {

/// \brief Options of the scattered reconstruction.
struct ScatteredRbfParams {
  OnionFrame frame = OnionFrame::ViewRelative;
  RbfParams rbf;  ///< r0 unset: the median nearest-neighbour distance among the samples
};

/// \brief The 81 x 81 table interpolated, per channel, from every sample of the set (any kind:
/// point samples of `sample --uniform`, or slice samples) at its own light and view directions.
/// Samples at the same directions are averaged first. Negatives are clipped to 0. Throws
/// ReconstructionError for an empty set, a non-finite sample or an interpolant that is not
/// finite (params for which the system is singular in floating point), ReconArgumentError
/// for invalid params.
Abrdf reconstructScattered(const SliceSet& samples, const ScatteredRbfParams& params = {});

}  // namespace slicecap::recon
