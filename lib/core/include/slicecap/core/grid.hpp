// The Bonn 81-direction grid (docs/method.md §1.1): rings, order, index <-> (theta, phi).
#pragma once

#include <array>
#include <optional>
#include <stdexcept>

namespace slicecap {

/// \brief A direction on the hemisphere: elevation from the normal and azimuth, both in degrees.
struct Direction {
  double thetaDeg = 0.0;
  double phiDeg = 0.0;
};

/// \brief A unit vector; x = sin(theta) cos(phi), y = sin(theta) sin(phi), z = cos(theta).
struct UnitVector {
  double x = 0.0, y = 0.0, z = 1.0;
};

/// \brief The unit vector of a direction (azimuth taken as counter-clockwise, docs/method.md §1.2).
UnitVector toUnitVector(const Direction& direction);

/// \brief The direction of a vector with z >= 0 (it need not be normalised; zero length throws
/// CoreError). Azimuth in [0, 360).
Direction toDirection(const UnitVector& vector);

/// \brief The angle between two directions, degrees in [0, 180].
double angleBetweenDeg(const Direction& a, const Direction& b);

/// \brief One elevation ring of the grid: every ring starts at azimuth 0 and steps 360 / count.
struct Ring {
  int thetaDeg;    ///< elevation of the ring
  int count;       ///< number of azimuths on it
  int firstIndex;  ///< direction index of azimuth 0
  constexpr double stepDeg() const { return 360.0 / count; }
  constexpr double azimuthDeg(int azimuthIndex) const { return azimuthIndex * stepDeg(); }
  constexpr int index(int azimuthIndex) const { return firstIndex + azimuthIndex; }
};

namespace bonn {

inline constexpr int kDirectionCount = 81;
inline constexpr int kRingCount = 6;
inline constexpr std::array<Ring, kRingCount> kRings{{
    {0, 1, 0},
    {15, 6, 1},
    {30, 12, 7},
    {45, 18, 19},
    {60, 20, 37},
    {75, 24, 57},
}};

/// \brief The ring with this exact elevation (0, 15, ..., 75), or nullopt for any other value.
std::optional<int> ringOfElevation(double thetaDeg);

/// \brief The ring at this elevation; throws CoreError if there is none.
const Ring& ringAt(int thetaDeg);

/// \brief Ring number (0..5) of a direction index; throws std::out_of_range outside 0..80.
int ringOfIndex(int directionIndex);

/// \brief The direction of an index; throws std::out_of_range outside 0..80.
Direction direction(int directionIndex);

/// \brief cos(theta) of every direction, by index (the cosine weights of the paper's encoding
/// and of the prior's log map).
const std::array<double, kDirectionCount>& cosines();

/// \brief The index of a grid direction; throws CoreError when (theta, phi) is not on
/// the grid (to within 1e-6 deg; the azimuth is wrapped first, and ignored at the pole).
int indexOf(const Direction& direction);

}  // namespace bonn
}  // namespace slicecap
