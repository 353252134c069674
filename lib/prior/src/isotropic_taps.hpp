// The table entries through which the prior's isotropic part is read at a sample's own angles.
#pragma once

#include <vector>

#include "slicecap/core/grid.hpp"
#include "slicecap/core/grid_interpolation.hpp"

namespace slicecap::prior {

/// \brief The taps of the sample (light, view) turned about the normal so that the direction on the
/// coarser ring (fewer azimuths) sits at azimuth 0, where every ring has a grid direction; only
/// the other direction is then interpolated in azimuth, at the sample's own phi_v - phi_i, on the
/// finer ring. Why: the learned basis and mean are isotropic (the prior is trained on isotropic
/// tables only: MERL, isotropic RGL, Nielsen), so turning the sample changes nothing they model,
/// while reading them at the sample's unturned azimuths blends entries at phi_v - phi_i +- one ring
/// step (up to 16 taps), which smears a highlight by a whole bin whenever the sample falls between
/// grid azimuths. Throws slicecap::CoreError as tableTaps (a direction off the hemisphere).
std::vector<TableTap> isotropicTableTaps(const Direction& light, const Direction& view);

}  // namespace slicecap::prior
