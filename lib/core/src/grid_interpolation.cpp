// Linear interpolation of a Bonn-grid table at arbitrary directions.
#include "slicecap/core/grid_interpolation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "slicecap/core/angles.hpp"
#include "slicecap/core/core_error.hpp"

namespace slicecap {

std::array<DirectionTap, 2> ringAzimuthTaps(const Ring& ring, double phiDeg) {
  if (ring.count == 1) return {{{ring.firstIndex, 1.0}, {ring.firstIndex, 0.0}}};
  const double position = wrapDeg360(phiDeg) / ring.stepDeg();
  const int lower = static_cast<int>(std::floor(position));
  const double f = position - lower;
  return {{{ring.index(lower % ring.count), 1.0 - f}, {ring.index((lower + 1) % ring.count), f}}};
}

std::vector<DirectionTap> directionTaps(const Direction& direction) {
  if (!std::isfinite(direction.thetaDeg) || !std::isfinite(direction.phiDeg) ||
      direction.thetaDeg < 0.0) {
    throw CoreError("direction (theta " + std::to_string(direction.thetaDeg) +
                    ", phi " + std::to_string(direction.phiDeg) +
                    ") deg is not on the upper hemisphere");
  }
  const auto& rings = bonn::kRings;
  int upper = 1;
  while (upper < bonn::kRingCount - 1 && rings[upper].thetaDeg < direction.thetaDeg)
    ++upper;
  const Ring& lo = rings[upper - 1];
  const Ring& hi = rings[upper];
  const double t =
      std::clamp((direction.thetaDeg - lo.thetaDeg) / (hi.thetaDeg - lo.thetaDeg), 0.0, 1.0);
  std::vector<DirectionTap> taps;
  taps.reserve(4);
  for (const auto& [ring, ringWeight] : {std::pair{&lo, 1.0 - t}, std::pair{&hi, t}}) {
    if (ringWeight == 0.0) continue;
    for (const DirectionTap& tap : ringAzimuthTaps(*ring, direction.phiDeg)) {
      if (tap.weight != 0.0) taps.push_back({tap.index, tap.weight * ringWeight});
    }
  }
  return taps;
}

std::vector<TableTap> tableTaps(const Direction& light, const Direction& view) {
  const std::vector<DirectionTap> lightTaps = directionTaps(light);
  const std::vector<DirectionTap> viewTaps = directionTaps(view);
  std::vector<TableTap> taps;
  taps.reserve(lightTaps.size() * viewTaps.size());
  for (const DirectionTap& l : lightTaps) {
    for (const DirectionTap& v : viewTaps)
      taps.push_back({l.index, v.index, l.weight * v.weight});
  }
  return taps;
}

Rgb evaluate(const Abrdf& table, const Direction& light, const Direction& view) {
  Rgb value;
  for (const TableTap& tap : tableTaps(light, view))
    value += table.at(tap.light, tap.view) * tap.weight;
  return value;
}

}  // namespace slicecap
