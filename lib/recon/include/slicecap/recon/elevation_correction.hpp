// Samples moved to their slice's nominal elevation pair before the slice-sum (issue 31 item 4).
#pragma once

#include "slicecap/core/slice.hpp"

namespace slicecap::recon {

/// \brief The elevation lobe the correction uses: mean(R, G, B) ~ k cos^a(theta_i) cos^b(theta_v).
struct SeparableElevationLobe {
  double lightExponent = 0.0;  ///< a
  double viewExponent = 0.0;   ///< b
};

/// \brief Fits the lobe to every axial and diagonal sample at its measured elevations (least squares
/// on the logarithm of the channel mean; samples whose mean is not positive are left out). Why
/// this lobe: it is Method B's own model (METHOD.md 4.1, eq. 6) with one exponent per direction,
/// and over the +-2 deg a hand-held capture strays it only has to give the local slope of the
/// level with elevation, which the four measured pairs pin down. Returns exponents 0 (no
/// correction) when the samples do not determine them (fewer than two light or two view
/// elevations, e.g. only the 30/30 and 75/75 sweeps).
SeparableElevationLobe fitSeparableElevationLobe(const SliceSet& slices);

/// \brief The slices with each axial and diagonal sample moved to its slice's nominal elevation
/// pair: the value times (cos theta_i0 / cos theta_i)^a (cos theta_v0 / cos theta_v)^b, the
/// elevations set to the nominal ones, the azimuths kept. Point samples are unchanged. A capture
/// at its nominal elevations comes back unchanged to the bit. Throws nothing.
SliceSet correctedToNominalElevations(const SliceSet& slices, const SeparableElevationLobe& lobe);

/// \brief correctedToNominalElevations with the lobe fitted to the slices themselves.
SliceSet correctedToNominalElevations(const SliceSet& slices);

}  // namespace slicecap::recon
