// The isotropy test (lib/prior/src/isotropy_test.cpp): isotropic from anisotropic materials, axial
// slices that vary, diagonal slices that cannot tell, no slices.
#include "slicecap/prior/isotropy_test.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "../support/keep_pairs.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/prior/prior_location.hpp"
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
  EXPECT_THROW(testIsotropy(SliceSet{}), std::invalid_argument);
}

}  // namespace
}  // namespace slicecap::prior
