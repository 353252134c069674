// The fit's domain helpers (lib/fit/src/fit_data.hpp): the cube root behind the sRGB curve's power
// agrees with libm's to a few ulp over the whole range the fit feeds it, and the curve is the sRGB
// curve.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fit_data.hpp"

namespace slicecap::fit::detail {
namespace {

TEST(FitData, CubeRootWithinFourUlpOfLibm) {
  std::mt19937_64 random(7);
  // Cos-weighted values scaled by the table's largest: 1e-12 (a dark pair) to 1e4 (a model that
  // overshoots far past the table while the solver explores).
  std::uniform_real_distribution<double> decade(-12.0, 4.0);
  double worstUlp = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double x = std::pow(10.0, decade(random));
    const double exact = std::cbrt(x);
    const double ulp = std::nextafter(exact, INFINITY) - exact;
    worstUlp = std::max(worstUlp, std::abs(cubeRoot(x) - exact) / ulp);
  }
  EXPECT_LE(worstUlp, 4.0);
  // Exact cubes and the denormal-free small end.
  EXPECT_NEAR(cubeRoot(27.0), 3.0, 4e-15);
  EXPECT_NEAR(cubeRoot(1e-300), 1e-100, 4e-115);
}

TEST(FitData, SrgbCurveIsTheStandardCurve) {
  for (const double x : {0.0, 0.001, 0.0031308, 0.01, 0.18, 0.5, 1.0, 2.0}) {
    const double expected = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    EXPECT_NEAR(srgbCurve(x), expected, 1e-14) << x;
  }
}

}  // namespace
}  // namespace slicecap::fit::detail
