// Onion angles (Havran, Filip & Myszkowski 2010, as in SRC-4's ConvertThetaPhiToBetaAlpha).
#include "slicecap/recon/onion.hpp"

#include <algorithm>
#include <cmath>

#include "slicecap/core/angles.hpp"

namespace slicecap::recon {
namespace {

// The angles of the point (x, y) of the unit disc: asin is clamped because sin theta cos phi can
// exceed 1 by a rounding step.
OnionAngles fromDisc(double x, double y) {
  const double b = std::asin(std::clamp(x, -1.0, 1.0));
  const double cosB = std::cos(b);
  const double a = cosB < 1e-5 ? 0.0 : std::asin(std::clamp(y / cosB, -1.0, 1.0));
  return {a, b};
}

}  // namespace

OnionAngles onionAngles(const Direction& d) {
  const double sinTheta = std::sin(degToRad(d.thetaDeg));
  const double phi = degToRad(d.phiDeg);
  return fromDisc(sinTheta * std::cos(phi), sinTheta * std::sin(phi));
}

OnionAngles onionAnglesRelativeToView(const Direction& light, double viewPhiDeg) {
  const double sinTheta = std::sin(degToRad(light.thetaDeg));
  const double relative = degToRad(light.phiDeg - viewPhiDeg);
  return fromDisc(sinTheta * std::sin(relative), -sinTheta * std::cos(relative));
}

FeaturePoint onionFeatures(const Direction& light, const Direction& view, OnionFrame frame) {
  const OnionAngles l = frame == OnionFrame::ViewRelative
                            ? onionAnglesRelativeToView(light, view.phiDeg)
                            : onionAngles(light);
  const OnionAngles v = onionAngles(view);
  return {l.aRad, l.bRad, v.aRad, v.bRad};
}

}  // namespace slicecap::recon
