// Samples moved to their slice's nominal elevation pair before the slice-sum (issue 31 item 4).
#pragma once

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::recon {

/// \brief The elevation lobe the correction uses: mean(R, G, B) ~ k cos^a(theta_i) cos^b(theta_v).
struct SeparableElevationLobe {
  double lightExponent = 0.0;  ///< a
  double viewExponent = 0.0;   ///< b
};

/// \brief Fits the lobe to every axial and diagonal sample at its measured elevations (least
/// squares on the logarithm of the channel mean; samples whose mean is not positive are left out).
/// Why this lobe: it is Method B's own model (docs/method.md §4.1, eq. 6) with one exponent per
/// direction, and over the +-2 deg a hand-held capture strays it only has to give the local slope
/// of the level with elevation, which the four measured pairs pin down. Returns exponents 0 (no
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

/// \brief The slices with each axial and diagonal sample moved to its slice's nominal elevation
/// pair along a full table's local change with elevation at the sample's own azimuths: the value
/// times exp(s_i (theta_i0 - theta_i) + s_v (theta_v0 - theta_v)), where s_i is the slope per
/// degree of log(the table's channel mean) along the light elevation between the rings around
/// the nominal one (15 deg either side; at 75 deg the 60 deg ring and the 75 deg one), the view's
/// elevation and both azimuths held, and s_v likewise along the view; 0 where a ring value is 0.
/// Why: one lobe of elevation for all azimuths cannot follow a highlight or a sheen that moves
/// with azimuth; a first reconstruction of the same slices can. A straight line in degrees was
/// chosen over a cosine lobe through the same two rings on the built-in isotropic materials (apart
/// from the anisotropic ones the goal is measured on): Method B's dE with +-2 deg jitter over the
/// jitter-free capture's, mean / worst, 1.038 / 1.102 against 1.066 / 1.219 (and 1.056 / 1.220 for
/// the fitted lobe alone; bench/measured_angles_eval --isotropic). Point samples are unchanged; a
/// capture at its nominal elevations comes back unchanged to the bit. Throws nothing.
SliceSet correctedToNominalElevations(const SliceSet& slices, const Abrdf& localModel);

}  // namespace slicecap::recon
