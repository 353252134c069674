// The fit's domain helpers (lib/fit/src/fit_data.hpp): the cube root behind the sRGB curve's power
// agrees with libm's to a few ulp over the whole range the fit feeds it, and the curve is the sRGB
// curve.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fit_data.hpp"

namespace slicecap::fit::detail {
namespace {

TEST(FitData, CubeRootWithinThreeUlpOfTheCorrectlyRoundedRoot) {
  std::mt19937_64 random(7);
  // Cos-weighted values scaled by the table's largest: 1e-12 (a dark pair) to 1e4 (a model that
  // overshoots far past the table while the solver explores).
  std::uniform_real_distribution<double> decade(-12.0, 4.0);
  double worstUlp = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double x = std::pow(10.0, decade(random));
    // The root in long double (64 or 113 bits of mantissa) rounded once to double.
    const double exact = static_cast<double>(std::cbrt(static_cast<long double>(x)));
    const double ulp = std::nextafter(exact, INFINITY) - exact;
    worstUlp = std::max(worstUlp, std::abs(cubeRoot(x) - exact) / ulp);
  }
  EXPECT_LE(worstUlp, 3.0);
  EXPECT_NEAR(cubeRoot(27.0), 3.0, 4e-15);
  // Outside the guess's range: libm's answer, not the bit trick's (which gives 2.7e-104 at 0
  // and NaN where 2 x overflows).
  EXPECT_EQ(cubeRoot(0.0), 0.0);
  EXPECT_EQ(cubeRoot(1e-310), std::cbrt(1e-310));
  EXPECT_EQ(cubeRoot(1e305), std::cbrt(1e305));
  EXPECT_EQ(cubeRoot(INFINITY), INFINITY);
}

TEST(FitData, SrgbCurveIsTheStandardCurve) {
  for (const double x : {0.0, 0.001, 0.0031308, 0.01, 0.18, 0.5, 1.0, 2.0}) {
    const double expected = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    EXPECT_NEAR(srgbCurve(x), expected, 1e-14) << x;
  }
}

}  // namespace
}  // namespace slicecap::fit::detail
