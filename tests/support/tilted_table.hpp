// A GGX material tabulated under a tilted shading normal with light and view turned into the
// tilted frame by hand (dot products with the frame's axes), independent of the fit's tilted lobe
// (lib/fit/src/tilted_lobe.hpp): the truth of the texture fit's tilt tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::test::tilt {

using fit::FittedMaterial;

struct Vec {
  double x, y, z;
};
inline double dot(const Vec& a, const Vec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec unit(const Vec& a) {
  const double n = std::sqrt(dot(a, a));
  return {a.x / n, a.y / n, a.z / n};
}
inline Vec cross(const Vec& a, const Vec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The normal tilted by `tiltDeg` toward azimuth `azimuthDeg`.
inline Vec tiltedNormal(double tiltDeg, double azimuthDeg) {
  const double t = tiltDeg * std::numbers::pi / 180.0, a = azimuthDeg * std::numbers::pi / 180.0;
  return {std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t)};
}

// The BRDF f_eff with f eff cos_i = f' cos_i': `flat` (its tangent at `flat.tangentDeg` in the
// untilted plane) evaluated with light and view written in the frame of `normal`, whose tangent
// is the untilted tangent with its component along `normal` removed. Zero behind the tilted
// surface.
inline Abrdf tabulateTilted(FittedMaterial flat, const Vec& normal) {
  const double t = flat.tangentDeg * std::numbers::pi / 180.0;
  const Vec untilted{std::cos(t), std::sin(t), 0.0};
  const double along = dot(untilted, normal);
  const Vec tangent = unit({untilted.x - along * normal.x, untilted.y - along * normal.y,
                            untilted.z - along * normal.z});
  const Vec bitangent = cross(normal, tangent);
  flat.tangentDeg = 0.0;  // in the tilted frame the tangent is x
  return tabulateOnGrid([&](const UnitVector& l, const UnitVector& v) {
    const Vec lw{l.x, l.y, l.z}, vw{v.x, v.y, v.z};
    const UnitVector lt{dot(lw, tangent), dot(lw, bitangent), dot(lw, normal)};
    const UnitVector vt{dot(vw, tangent), dot(vw, bitangent), dot(vw, normal)};
    if (lt.z <= 0.0 || vt.z <= 0.0) return Rgb{};
    Rgb value = flat.evaluate(lt, vt);
    for (std::size_t c = 0; c < 3; ++c)
      value[c] *= lt.z / l.z;
    return value;
  });
}

// The angle between a fitted normal and a true one, deg.
inline double angleDeg(const UnitVector& a, const Vec& b) {
  return std::acos(std::clamp(dot({a.x, a.y, a.z}, b), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

}  // namespace slicecap::test::tilt
