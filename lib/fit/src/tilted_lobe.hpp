// The texture fit's lobe with a tilted shading normal (docs/material-fit.md "Texture mode"): light
// and view expressed in the tilted frame, templated so that the Ceres cost (Jets) and plain doubles
// share one formula.
#pragma once

#include <cmath>
#include <numbers>

#include "lobe_terms.hpp"

namespace slicecap::fit::detail {

/// \brief Below this cosine to the tilted normal a light or view is behind the shading surface.
inline constexpr double kTiltedHorizonCosine = 1e-6;
/// \brief A pair whose light or view is within this cosine (10 deg) of the tilted horizon is faded
/// out of the fit (smoothly, to 0 at the horizon): there the normal-mapped model jumps to zero (a
/// renderer's clamp), and a pair on one side of the jump or the other would pin the tilt (a
/// single such pair left 3.6 levels RMS on an exact table). Every direction of the Bonn grid (75
/// deg at most) is outside it when the normal is flat, so a flat texel's fit is the table fit's.
inline constexpr double kHorizonFadeCosine = 0.17;

/// \brief 0 at or below the tilted horizon, 1 from kHorizonFadeCosine up, smoothstep between.
template <typename T>
T horizonFade(const T& cosine) {
  if (cosine >= kHorizonFadeCosine) return T(1.0);
  const T s = cosine / kHorizonFadeCosine;
  return s * s * (3.0 - 2.0 * s);
}

/// \brief The two parameter-dependent factors of one pair's value: f cos_i (geometric) equals
/// (albedo / pi diffuse + F specular) cos_i, so both already carry the tilted cosine ratio.
template <typename T>
struct TiltedShape {
  T diffuse;   ///< n'.l / n.l: glTF's normal map tilts the diffuse cosine too
  T specular;  ///< D G2 / (4 n'.l n'.v) in the tilted frame, times n'.l / n.l
  T weight;    ///< the pair's weight in the fit: horizonFade of n'.l times that of n'.v
};

/// \brief The tilted frame: the shading normal n' = (nx, ny, sqrt(1 - nx^2 - ny^2)) in the
/// texel's frame; the tangent at (cosT, sinT, 0) projected onto the plane normal to n' (glTF's
/// anisotropy direction lives in the mesh's tangent plane; a renderer turns it onto the perturbed
/// normal's); the bitangent n' x t'. Built once per parameter set, not per pair.
template <typename T>
struct TiltedFrame {
  T tx, ty, tz, bx, by, bz, nx, ny, nz;
};

template <typename T>
TiltedFrame<T> tiltedFrame(const T& cosT, const T& sinT, const T& nx, const T& ny) {
  using std::sqrt;
  TiltedFrame<T> f;
  f.nx = nx;
  f.ny = ny;
  f.nz = sqrt(1.0 - nx * nx - ny * ny);
  const T tn = cosT * nx + sinT * ny;
  const T tx = cosT - tn * nx, ty = sinT - tn * ny, tz = -tn * f.nz;
  const T tLength = sqrt(tx * tx + ty * ty + tz * tz);
  f.tx = tx / tLength;
  f.ty = ty / tLength;
  f.tz = tz / tLength;
  f.bx = ny * f.tz - f.nz * f.ty;
  f.by = f.nz * f.tx - nx * f.tz;
  f.bz = nx * f.ty - ny * f.tx;
  return f;
}

/// \brief One pair's shape in the tilted frame `f`. A pair with light or view behind the tilted
/// surface reflects nothing, as a renderer clamping n'.l and n'.v. With a flat frame this is
/// ggxSpecular exactly (the grid's directions are all above the untilted horizon).
template <typename T>
TiltedShape<T> tiltedShape(const PairGeometry& g, const T& alphaT, const T& alphaB,
                           const TiltedFrame<T>& f) {
  using std::sqrt;
  const auto dotT = [&](const UnitVector& w) { return w.x * f.tx + w.y * f.ty + w.z * f.tz; };
  const auto dotB = [&](const UnitVector& w) { return w.x * f.bx + w.y * f.by + w.z * f.bz; };
  const auto dotN = [&](const UnitVector& w) { return w.x * f.nx + w.y * f.ny + w.z * f.nz; };
  const T cosL = dotN(g.light), cosV = dotN(g.view);
  if (cosL <= kTiltedHorizonCosine || cosV <= kTiltedHorizonCosine) return {T(0.0), T(0.0), T(0.0)};
  const T ratio = cosL / g.light.z;
  const T hx = dotT(g.half), hy = dotB(g.half), hz = dotN(g.half);
  const T lx = dotT(g.light), ly = dotB(g.light), vx = dotT(g.view), vy = dotB(g.view);
  const T aT2 = alphaT * alphaT, aB2 = alphaB * alphaB;
  const T s = hx * hx / aT2 + hy * hy / aB2 + hz * hz;
  const T distribution = 1.0 / (std::numbers::pi * alphaT * alphaB * s * s);
  const T lambdaL = (sqrt(1.0 + (aT2 * lx * lx + aB2 * ly * ly) / (cosL * cosL)) - 1.0) / 2.0;
  const T lambdaV = (sqrt(1.0 + (aT2 * vx * vx + aB2 * vy * vy) / (cosV * cosV)) - 1.0) / 2.0;
  const T specular = distribution / ((1.0 + lambdaL + lambdaV) * (4.0 * cosL * cosV));
  return {ratio, specular * ratio, horizonFade(cosL) * horizonFade(cosV)};
}

}  // namespace slicecap::fit::detail
