// The fit's domain helpers (lib/fit/src/fit_data.hpp): the curve, computed through a cube root
// instead of pow(), is the sRGB curve.
#include <gtest/gtest.h>

#include <cmath>

#include "fit_data.hpp"

namespace slicecap::fit::detail {
namespace {

TEST(FitData, SrgbCurveIsTheStandardCurve) {
  for (const double x : {0.0, 0.001, 0.0031308, 0.01, 0.18, 0.5, 1.0, 2.0}) {
    const double expected = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    EXPECT_NEAR(srgbCurve(x), expected, 1e-14) << x;
  }
}

}  // namespace
}  // namespace slicecap::fit::detail
