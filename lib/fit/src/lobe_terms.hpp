// The fitted material's terms, templated so that the Ceres residual (Jets) and the plain evaluation
// (doubles) share one formula.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slicecap/core/grid.hpp"
#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/fit/sheen_albedo.hpp"

namespace slicecap::fit::detail {

/// \brief Everything about one (light, view) pair that does not depend on the parameters.
struct PairGeometry {
  UnitVector light, view, half;  ///< world frame (z = normal, x = azimuth 0)
  double fresnelWeight = 0.0;    ///< (1 - l.h)^5, rotation-invariant
  double sheenVisibility = 0.0;  ///< 1 / (4 (cos_i + cos_v - cos_i cos_v))
  double logSinSquaredHalf = 0.0;  ///< log(1 - h.z^2), floored so that it is finite
  double coatFresnel = 0.0;  ///< the clear coat's Schlick 0.04 + 0.96 (1 - cos_v)^5
};

inline PairGeometry pairGeometry(const UnitVector& l, const UnitVector& v) {
  PairGeometry g;
  g.light = l;
  g.view = v;
  const double hx = l.x + v.x, hy = l.y + v.y, hz = l.z + v.z;
  const double length = std::sqrt(hx * hx + hy * hy + hz * hz);
  g.half = {hx / length, hy / length, hz / length};
  const double cosLh = std::clamp(l.x * g.half.x + l.y * g.half.y + l.z * g.half.z, 0.0, 1.0);
  g.fresnelWeight = std::pow(1.0 - cosLh, 5.0);
  g.sheenVisibility = 1.0 / (4.0 * (l.z + v.z - l.z * v.z));
  // At h = n (light = view = normal) sin h = 0, and d/dr of 0^(1/r) is log(0): a floor far
  // below any value that matters keeps the Jacobian finite.
  g.logSinSquaredHalf = std::log(std::max(1.0 - g.half.z * g.half.z, 1e-12));
  g.coatFresnel = kCoatF0 + (1.0 - kCoatF0) * std::pow(1.0 - std::clamp(v.z, 0.0, 1.0), 5.0);
  return g;
}

/// \brief D G2 / (4 cos_i cos_v) of anisotropic GGX (height-correlated Smith), the tangent at
/// angle (cosT, sinT) from x: the factor the Fresnel term multiplies.
template <typename T>
T ggxSpecular(const PairGeometry& g, const T& alphaT, const T& alphaB, const T& cosT,
              const T& sinT) {
  using std::sqrt;
  const auto local = [&](const UnitVector& w, T& x, T& y) {
    x = w.x * cosT + w.y * sinT;
    y = -w.x * sinT + w.y * cosT;
  };
  T hx, hy, lx, ly, vx, vy;
  local(g.half, hx, hy);
  local(g.light, lx, ly);
  local(g.view, vx, vy);
  const T aT2 = alphaT * alphaT, aB2 = alphaB * alphaB;
  const T s = hx * hx / aT2 + hy * hy / aB2 + g.half.z * g.half.z;
  const T distribution = 1.0 / (std::numbers::pi * alphaT * alphaB * s * s);
  const T lambdaL = (sqrt(1.0 + (aT2 * lx * lx + aB2 * ly * ly) / (g.light.z * g.light.z)) - 1.0) / 2.0;
  const T lambdaV = (sqrt(1.0 + (aT2 * vx * vx + aB2 * vy * vy) / (g.view.z * g.view.z)) - 1.0) / 2.0;
  return distribution / ((1.0 + lambdaL + lambdaV) * (4.0 * g.light.z * g.view.z));
}

/// \brief The Charlie sheen lobe D_sheen V, without its colour.
template <typename T>
T sheenLobe(const PairGeometry& g, const T& roughness) {
  using std::exp;
  // sin^(1/r) h = exp(log(sin^2 h) / (2 r)): one exp a pair, the logarithm kept with the pair.
  const T inverse = 1.0 / roughness;
  return (2.0 + inverse) * exp(g.logSinSquaredHalf * (0.5 * inverse)) / (2.0 * std::numbers::pi) *
         g.sheenVisibility;
}

}  // namespace slicecap::fit::detail

namespace slicecap::fit::detail {

/// \brief KHR_materials_sheen's lobe D_charlie V_charlie (its "Charlie" visibility, alpha_g = r),
/// without its colour.
template <typename T>
T khrSheenLobe(const PairGeometry& g, const T& roughness) {
  using std::exp;
  const T inverse = 1.0 / roughness;
  return (2.0 + inverse) * exp(g.logSinSquaredHalf * (0.5 * inverse)) / (2.0 * std::numbers::pi) *
         charlieVisibility(g.light.z, g.view.z, roughness);
}

/// \brief max(E(cos_v), E(cos_l)): 1 - s times it is the extension's
/// min(1 - s E(VdotN), 1 - s E(LdotN)).
template <typename T>
T khrSheenAlbedoMax(const PairGeometry& g, const T& roughness) {
  const T light = sheenAlbedo(g.light.z, roughness), view = sheenAlbedo(g.view.z, roughness);
  return valueOf(light) > valueOf(view) ? light : view;
}

}  // namespace slicecap::fit::detail
