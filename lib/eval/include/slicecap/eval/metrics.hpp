// The paper's 8-bit error metrics (docs/method.md §1.4, §6.1) and a linear-domain
// error.
#pragma once

#include <array>

#include "slicecap/core/abrdf.hpp"

namespace slicecap::eval {

/// \brief Upper bound reported for PSNR, so identical tables give a finite number.
inline constexpr double kMaxPsnrDb = 100.0;

/// \brief Errors of a test table against a reference.
struct Metrics {
  double deltaE = 0.0;        ///< mean CIE76 dE over the 6561 light/view pairs
  double rmse = 0.0;          ///< RMSE of 8-bit values over 6561 x 3
  double psnrDb = 0.0;        ///< 20 log10(255 / rmse), at most kMaxPsnrDb
  double relativeRmse = 0.0;  ///< ||test - ref|| / ||ref|| over the linear BRDF values
  /// \brief The test's largest linear value over the reference's (any direction pair, any
  /// channel): a sharp highlight lost to clipping shows here (<< 1) while dE hardly notices.
  double peakRatio = 1.0;
};

/// \brief The paper's encoding of a table: times cos(theta_i), divided by `referenceMax` (the
/// reference's cos-weighted maximum), clipped to [0, 1], sRGB-encoded, x255, rounded.
std::array<unsigned char, Abrdf::kValueCount> encodePaper8Bit(const Abrdf& table,
                                                              double referenceMax);

/// \brief The largest cos(theta_i)-weighted value of a table over all 6561 x 3.
double cosWeightedMaximum(const Abrdf& table);

/// \brief Whether `reference` can be compared against: it has a positive cos-weighted value to
/// normalise by (a material that reflects nothing has none).
bool canCompareAgainst(const Abrdf& reference);

/// \brief All metrics of `test` against `reference`. Throws EvalError unless
/// canCompareAgainst(reference) (nothing to normalise by): ask it first where that can be.
Metrics compare(const Abrdf& reference, const Abrdf& test);

/// \brief sRGB OETF (linear [0, 1] -> encoded [0, 1]) and its inverse.
double srgbEncode(double linear);
double srgbDecode(double encoded);

/// \brief CIE76 dE of two 8-bit sRGB colours (via linear sRGB, XYZ D65, L*a*b* with the sRGB
/// white).
double deltaE76(const std::array<unsigned char, 3>& a, const std::array<unsigned char, 3>& b);

}  // namespace slicecap::eval
