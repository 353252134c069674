// The isotropy test's per-slice scores on hand-made diagonal slices: the mirror term counts only
// where it can show anisotropy (mixed elevations, docs/method.md §8.1).
#include <gtest/gtest.h>

#include <cmath>

#include "slicecap/core/angles.hpp"
#include "slicecap/prior/isotropy_test.hpp"

namespace slicecap::prior {
namespace {

// A diagonal slice whose value repeats every half turn but is not mirror symmetric:
// 1 + 0.8 sin(2x) at the view azimuth x, so s(x + 180) = s(x) and s(360 - x) != s(x).
SliceSet halfTurnSymmetricDiagonal(int thetaIDeg, int thetaVDeg) {
  SliceSet slices;
  for (int k = 0; k < 24; ++k) {
    const double xDeg = 15.0 * k;
    const double value = 1.0 + 0.8 * std::sin(degToRad(2.0 * xDeg));
    slices.add({SliceKind::Diagonal, {thetaIDeg, thetaVDeg}},
               {{double(thetaIDeg), std::fmod(360.0 - xDeg, 360.0)},
                {double(thetaVDeg), xDeg},
                {value, value, value}});
  }
  return slices;
}

TEST(IsotropyScores, MixedElevationDiagonalSlicesAreHeldToMirrorSymmetry) {
  const IsotropyVerdict v = testIsotropy(halfTurnSymmetricDiagonal(30, 75), IsotropyParams{});
  ASSERT_EQ(v.slices.size(), 1u);
  EXPECT_TRUE(v.slices[0].informative);
  // Half the terms (the half turns) are zero; the mirror terms, log(1.8 / 0.2) apart at most,
  // leave an RMS well above zero.
  EXPECT_GT(v.slices[0].score, 0.5);
  EXPECT_EQ(v.diagonalScore, v.slices[0].score);
}

TEST(IsotropyScores, EqualElevationDiagonalSlicesScoreTheHalfTurnOnly) {
  const IsotropyVerdict v = testIsotropy(halfTurnSymmetricDiagonal(45, 45), IsotropyParams{});
  ASSERT_EQ(v.slices.size(), 1u);
  EXPECT_FALSE(v.slices[0].informative);
  EXPECT_LT(v.slices[0].score, 1e-9) << "a half-turn symmetric slice has no half-turn asymmetry";
}

}  // namespace
}  // namespace slicecap::prior
