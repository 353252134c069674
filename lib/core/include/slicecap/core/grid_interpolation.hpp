// A table's value at any light and view directions: linear interpolation on the Bonn grid.
#pragma once

#include <array>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"

namespace slicecap {

/// \brief One grid direction and its weight in an interpolated direction.
struct DirectionTap {
  int index = 0;
  double weight = 0.0;
};

/// \brief Up to two taps on a ring at any azimuth: periodic linear between its neighbouring
/// azimuths (one tap of weight 1 on a ring of one). Weights sum to 1; a zero-weight tap may be
/// present.
std::array<DirectionTap, 2> ringAzimuthTaps(const Ring& ring, double phiDeg);

/// \brief Up to four taps for a direction: periodic linear in azimuth on the two rings around its
/// elevation, linear in elevation between them. Elevations above 75 deg take the 75 deg ring (no
/// extrapolation toward the horizon); negative ones are an error (CoreError), as are
/// non-finite angles. Zero-weight taps are dropped; weights sum to 1.
std::vector<DirectionTap> directionTaps(const Direction& direction);

/// \brief One table entry and its weight.
struct TableTap {
  int light = 0;
  int view = 0;
  double weight = 0.0;
};

/// \brief The table entries (up to 16) that make up the value at (light, view): the product of the
/// two directions' taps. This is the linear measurement operator of one sample.
std::vector<TableTap> tableTaps(const Direction& light, const Direction& view);

/// \brief The interpolated table value at any light and view directions (tableTaps).
Rgb evaluate(const Abrdf& table, const Direction& light, const Direction& view);

}  // namespace slicecap
