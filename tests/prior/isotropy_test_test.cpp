// The isotropy test (lib/prior/src/isotropy_test.cpp): isotropic from anisotropic materials, axial
// slices that vary, diagonal slices that cannot tell, no slices; the per-slice scores on hand-made
// diagonal slices (the mirror term counts only where it can show anisotropy, docs/method.md §8.1).
#include "slicecap/prior/isotropy_test.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "../support/keep_pairs.hpp"
#include "slicecap/core/angles.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/prior/prior_model.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::prior {
namespace {

using test::keepPairs;

TEST(IsotropyTest, TellsIsotropicFromAnisotropicMaterials) {
  recon::ExtractionParams diagonal;
  diagonal.diagonalOnly = true;
  for (const models::NamedMaterial& m : models::isotropicMaterials()) {
    const IsotropyVerdict v = testIsotropy(
        recon::extractSlices(models::tabulate(*m.model), diagonal), defaultPriorModel());
    EXPECT_TRUE(v.isotropic) << m.name << ": " << v.reason;
    EXPECT_TRUE(v.informative) << "the 30/75 and 75/30 diagonal slices can show anisotropy";
  }
  // Grain at 30 deg and along phi = 0, which the symmetry of the diagonal slices cannot show.
  for (const char* name : {"brushed-steel-30", "brushed-aluminium"}) {
    const IsotropyVerdict v =
        testIsotropy(recon::extractSlices(models::tabulate(*models::findMaterial(name)), diagonal),
                     defaultPriorModel());
    EXPECT_FALSE(v.isotropic) << name << ": " << v.reason;
    EXPECT_LT(v.priorScoreRatio, IsotropyParams{}.priorScoreRatio) << name;
  }
}

TEST(IsotropyTest, AxialSlicesThatVaryMeanAnisotropy) {
  const IsotropyVerdict v = testIsotropy(
      recon::extractSlices(models::tabulate(*models::findMaterial("brushed-brass-120"))));
  EXPECT_FALSE(v.isotropic) << v.reason;
  EXPECT_GT(v.axialScore, IsotropyParams{}.axialThreshold);
}

TEST(IsotropyTest, EqualElevationDiagonalSlicesCannotTell) {
  recon::ExtractionParams diagonal;
  diagonal.diagonalOnly = true;
  const Abrdf truth = models::tabulate(*models::findMaterial("brushed-steel-30"));
  const SliceSet twoSweeps = keepPairs(recon::extractSlices(truth, diagonal), {{30, 30}, {75, 75}});
  const IsotropyVerdict v = testIsotropy(twoSweeps, defaultPriorModel());
  EXPECT_FALSE(v.informative);
  EXPECT_NE(v.reason.find("cannot tell"), std::string::npos) << v.reason;
}

TEST(IsotropyTest, NeedsSlices) {
  EXPECT_THROW(testIsotropy(SliceSet{}), prior::PriorError);
}

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
