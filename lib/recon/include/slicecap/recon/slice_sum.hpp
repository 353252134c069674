// Reconstruction of one measured subspace from its two slices (eq. 2-4) or its diagonal slice (eq.
// 5).
#pragma once

#include "slicecap/core/slice.hpp"
#include "slicecap/recon/periodic_signal.hpp"
#include "slicecap/recon/subspace.hpp"

namespace slicecap::recon {

/// \brief How a grid point is mapped to its slice parameters when halving angles (docs/method.md §3.2).
enum class TorusRule {
  FundamentalSquare,  ///< the pre-image inside [0,360)^2 (the paper's rotated image; default)
  PiSymmetric,        ///< the average of slice(x) and slice(x + 180)
};

/// \brief Slice parameters of a grid point: u* for the axial slice, w* for the diagonal slice.
struct SliceCoordinates {
  double axialDeg = 0.0;     ///< u* = ((phi_i + phi_v - 15) / 2) mod 360
  double diagonalDeg = 0.0;  ///< w* = (180 + (phi_v - phi_i) / 2) mod 360
};

/// \brief The resolved mapping of docs/method.md §3.2; inputs in [0, 360).
SliceCoordinates sliceCoordinates(double phiIDeg, double phiVDeg);

/// \brief A slice as a periodic signal of its parameter; throws ReconstructionError naming the
/// slice when it has no samples, a non-finite one, or is a group of point samples.
PeriodicSignal toSignal(const Slice& slice);

/// \brief Eq. 2-4 with the resolved mapping and the normalisation of docs/method.md §3.3, per channel, on
/// the subspace's own ring grid. Slices must be of the same elevation pair (ReconstructionError).
Subspace reconstructSubspace(const Slice& axial, const Slice& diagonal,
                             TorusRule rule = TorusRule::FundamentalSquare);

/// \brief Eq. 5: value = s_D(w*), for isotropic materials (diagonal slice only).
Subspace reconstructIsotropicSubspace(const Slice& diagonal,
                                      TorusRule rule = TorusRule::FundamentalSquare);

}  // namespace slicecap::recon
