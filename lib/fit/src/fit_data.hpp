// The table as the fit sees it: per light/view pair its fixed geometry, its cos-weighted scale and
// its three target values in the fit's domain.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "lobe_terms.hpp"
#include "slicecap/core/abrdf.hpp"

namespace slicecap::fit::detail {

/// \brief Parameter block of the GGX part: diffuse albedo RGB, f0 RGB, log alpha_t, log alpha_b,
/// tangent (rad), f90. Logs keep the alphas positive and their steps relative.
inline constexpr int kGgxParameters = 10;
/// \brief Parameter block of the sheen part: sheen colour RGB, log sheen roughness.
inline constexpr int kSheenParameters = 4;
/// \brief Parameter block of the clear coat: weight w, log alpha_c.
inline constexpr int kCoatParameters = 2;

/// \brief The fit's residuals (MaterialCost): per pair i and channel c,
/// 255 srgbCurve(f_c(pair i) scale_i) - target_i,c, with f the FittedMaterial's BRDF.
struct FitData {
  std::vector<PairGeometry> pairs;
  std::vector<double> scale;                  ///< cos(theta_i) / M per pair
  std::vector<std::array<double, 3>> target;  ///< 255 g(t cos_i / M) per pair and channel
  int residualCount() const { return static_cast<int>(pairs.size()) * 3; }
};

/// \brief The fit's domain for a table whose largest cos-weighted value is M (> 0).
FitData makeFitData(const Abrdf& table);

/// \brief Every `stride`-th pair of `data` (a quick first look at a start).
FitData everyNthPair(const FitData& data, int stride);

/// \brief x^(5/12) as cbrt(x)^(5/4): the sRGB curve's power without pow(), which took a third of
/// the fit's time. Exact to rounding.
inline double powFiveTwelfths(double x) {
  const double c = std::cbrt(x);
  return c * std::sqrt(std::sqrt(c));
}

/// \brief The sRGB curve, continued past 1 by the same power law (a model may overshoot).
inline double srgbCurve(double x) {
  if (x <= 0.0031308) return 12.92 * x;
  return 1.055 * powFiveTwelfths(x) - 0.055;
}

/// \brief d srgbCurve / dx, given x and srgbCurve(x).
inline double srgbSlope(double x, double curve) {
  if (x <= 0.0031308) return 12.92;
  return 1.055 * (5.0 / 12.0) * (curve + 0.055) / 1.055 / x;
}

}  // namespace slicecap::fit::detail
