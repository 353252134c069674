// Isotropic reading of the prior's basis at a sample's own relative azimuth.
#include "isotropic_taps.hpp"

#include <algorithm>
#include <cmath>

namespace slicecap::prior {
namespace {

// Azimuth count of the ring nearest to an elevation (the ring a sample was taken for).
int nearestRingCount(double thetaDeg) {
  const long ring = std::clamp(std::lround(thetaDeg / 15.0), 0L, long(bonn::kRingCount - 1));
  return bonn::kRings[std::size_t(ring)].count;
}

}  // namespace

std::vector<TableTap> isotropicTableTaps(const Direction& light, const Direction& view) {
  if (!std::isfinite(light.phiDeg) || !std::isfinite(view.phiDeg) ||
      !std::isfinite(light.thetaDeg) || !std::isfinite(view.thetaDeg))
    return tableTaps(light, view);  // tableTaps names the bad direction
  if (nearestRingCount(light.thetaDeg) <= nearestRingCount(view.thetaDeg))
    return tableTaps({light.thetaDeg, 0.0}, {view.thetaDeg, view.phiDeg - light.phiDeg});
  return tableTaps({light.thetaDeg, light.phiDeg - view.phiDeg}, {view.thetaDeg, 0.0});
}

}  // namespace slicecap::prior
