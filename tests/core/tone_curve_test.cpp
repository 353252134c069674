// ToneCurve: exact inversion, the standard curves' shapes, and named refusals.
#include "slicecap/core/tone_curve.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "slicecap/core/core_error.hpp"

namespace slicecap {
namespace {

TEST(ToneCurve, DecodeInvertsEncodeOnEveryCurve) {
  for (const ToneCurve& curve : {ToneCurve::srgb(), ToneCurve::imx708Tuning(), ToneCurve::linear()})
    for (double x = 0.0; x <= 1.0; x += 0.001)
      EXPECT_NEAR(curve.decode(curve.encode(x)), x, 1e-12) << curve.name() << " at " << x;
}

TEST(ToneCurve, SrgbTableFollowsTheStandardFormula) {
  const ToneCurve curve = ToneCurve::srgb();
  for (double x = 0.0; x <= 1.0; x += 0.0037) {
    const double exact = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
    EXPECT_NEAR(curve.encode(x), exact, 1e-4) << x;
  }
}

TEST(ToneCurve, Imx708CurveIsNotSrgbWhereItMatters) {
  // The reason the capture cannot decode a Pi's processed frames with the sRGB curve: at the
  // levels of a diffuse white reference and a dark window the two differ by several percent.
  const ToneCurve pi = ToneCurve::imx708Tuning(), srgb = ToneCurve::srgb();
  EXPECT_NEAR(pi.encode(1024.0 / 65535), 5040.0 / 65535, 1e-12);
  const double encodedWhite = 0.5, encodedDark = 0.1;
  const double ratioPi = pi.decode(encodedWhite) / pi.decode(encodedDark);
  const double ratioSrgb = srgb.decode(encodedWhite) / srgb.decode(encodedDark);
  EXPECT_GT(std::abs(ratioPi / ratioSrgb - 1.0), 0.05);
}

TEST(ToneCurve, ClampsOutsideTheUnitRange) {
  const ToneCurve curve = ToneCurve::imx708Tuning();
  EXPECT_EQ(curve.encode(-0.5), 0.0);
  EXPECT_EQ(curve.encode(7.0), 1.0);
  EXPECT_EQ(curve.decode(2.0), 1.0);
}

TEST(ToneCurve, RefusesACurveThatDoesNotRiseNamingThePoint) {
  try {
    ToneCurve("measured", {{0.0, 0.0}, {0.5, 0.6}, {0.6, 0.6}, {1.0, 1.0}});
    FAIL() << "a flat segment was accepted";
  } catch (const slicecap::CoreError& error) {
    EXPECT_NE(std::string(error.what()).find("'measured'"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("point 2"), std::string::npos) << error.what();
  }
  EXPECT_THROW(ToneCurve("x", {{0.0, 0.1}, {1.0, 1.0}}), slicecap::CoreError);
  EXPECT_THROW(ToneCurve("x", {{0.0, 0.0}, {0.9, 1.0}}), slicecap::CoreError);
}

}  // namespace
}  // namespace slicecap
