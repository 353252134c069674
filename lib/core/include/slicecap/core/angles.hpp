// Angle conversions and azimuth wrapping; degrees in files and on the command line, radians in
// math.
#pragma once

#include <cmath>
#include <numbers>

namespace slicecap {

/// \brief Degrees to radians.
constexpr double degToRad(double angleDeg) {
  return angleDeg * std::numbers::pi / 180.0;
}

/// \brief Radians to degrees.
constexpr double radToDeg(double angleRad) {
  return angleRad * 180.0 / std::numbers::pi;
}

/// \brief An azimuth taken mod 360 into [0, 360); non-finite input is returned unchanged.
inline double wrapDeg360(double azimuthDeg) {
  // Most azimuths are already in range or one turn above it (slice coordinates, ring positions):
  // there fmod is exact and equals these, and it costs more than the rest of a slice lookup.
  if (azimuthDeg >= 0.0 && azimuthDeg < 360.0) return azimuthDeg;
  if (azimuthDeg >= 360.0 && azimuthDeg < 720.0) return azimuthDeg - 360.0;
  double wrapped = std::fmod(azimuthDeg, 360.0);
  if (wrapped < 0.0) wrapped += 360.0;
  // fmod of a tiny negative number plus 360 can round up to exactly 360.
  return wrapped >= 360.0 ? 0.0 : wrapped;
}

/// \brief Signed smallest difference a - b of two azimuths, in (-180, 180].
inline double azimuthDifferenceDeg(double aDeg, double bDeg) {
  double difference = wrapDeg360(aDeg - bDeg);
  return difference > 180.0 ? difference - 360.0 : difference;
}

}  // namespace slicecap
