// The Bonn grid's index arithmetic.
#include "slicecap/core/grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "slicecap/core/angles.hpp"
#include "slicecap/core/core_error.hpp"

namespace slicecap {

UnitVector toUnitVector(const Direction& direction) {
  const double theta = degToRad(direction.thetaDeg);
  const double phi = degToRad(direction.phiDeg);
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Direction toDirection(const UnitVector& v) {
  const double length = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  if (!(length > 0.0)) throw CoreError("toDirection: zero-length vector");
  const double z = std::clamp(v.z / length, -1.0, 1.0);
  const double thetaDeg = radToDeg(std::acos(z));
  const double phiDeg =
      (v.x == 0.0 && v.y == 0.0) ? 0.0 : wrapDeg360(radToDeg(std::atan2(v.y, v.x)));
  return {thetaDeg, phiDeg};
}

double angleBetweenDeg(const Direction& a, const Direction& b) {
  const UnitVector u = toUnitVector(a), v = toUnitVector(b);
  return radToDeg(std::acos(std::clamp(u.x * v.x + u.y * v.y + u.z * v.z, -1.0, 1.0)));
}

namespace bonn {

std::optional<int> ringOfElevation(double thetaDeg) {
  for (int r = 0; r < kRingCount; ++r) {
    if (std::abs(thetaDeg - kRings[r].thetaDeg) < 1e-6) return r;
  }
  return std::nullopt;
}

const Ring& ringAt(int thetaDeg) {
  const auto ring = ringOfElevation(thetaDeg);
  if (!ring) {
    throw CoreError("no Bonn ring at elevation " + std::to_string(thetaDeg) + " deg");
  }
  return kRings[*ring];
}

int ringOfIndex(int directionIndex) {
  if (directionIndex < 0 || directionIndex >= kDirectionCount) {
    throw std::out_of_range("Bonn direction index " + std::to_string(directionIndex) +
                            " is outside 0..80");
  }
  int ring = kRingCount - 1;
  while (kRings[ring].firstIndex > directionIndex)
    --ring;
  return ring;
}

Direction direction(int directionIndex) {
  const Ring& ring = kRings[ringOfIndex(directionIndex)];
  return {static_cast<double>(ring.thetaDeg), ring.azimuthDeg(directionIndex - ring.firstIndex)};
}

const std::array<double, kDirectionCount>& cosines() {
  static const std::array<double, kDirectionCount> table = [] {
    std::array<double, kDirectionCount> c{};
    for (int d = 0; d < kDirectionCount; ++d)
      c[static_cast<std::size_t>(d)] = std::cos(degToRad(direction(d).thetaDeg));
    return c;
  }();
  return table;
}

int indexOf(const Direction& d) {
  const auto ringNumber = ringOfElevation(d.thetaDeg);
  auto fail = [&] {
    return CoreError("direction (theta " + std::to_string(d.thetaDeg) + ", phi " +
                     std::to_string(d.phiDeg) + ") deg is not on the Bonn grid");
  };
  if (!ringNumber) throw fail();
  const Ring& ring = kRings[*ringNumber];
  if (ring.count == 1) return ring.firstIndex;
  const double position = wrapDeg360(d.phiDeg) / ring.stepDeg();
  const double nearest = std::round(position);
  if (std::abs(position - nearest) * ring.stepDeg() > 1e-6) throw fail();
  return ring.index(static_cast<int>(nearest) % ring.count);
}

}  // namespace bonn
}  // namespace slicecap
