// The halfway method: isotropy detection, kept subspaces, exact diffuse, and better than Method B
// where B extrapolates.
#include "slicecap/recon/halfway_method.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "../support/test_support.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/argument_error.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/measured_subspaces.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::recon {
namespace {

Abrdf tableOf(const char* material) {
  return models::tabulate(*models::findMaterial(material));
}

TEST(HalfwayMethod, AxialVariationSeparatesIsotropicFromAnisotropicMaterials) {
  EXPECT_LT(*axialVariation(extractSlices(tableOf("blue-plastic"))), 1e-6);
  // Ideal slices of the 30/30 axial line fall between grid azimuths: interpolation, not zero.
  EXPECT_LT(*axialVariation(extractSlices(tableOf("red-plastic-ggx"))), 1e-3);
  EXPECT_GT(*axialVariation(extractSlices(tableOf("brushed-aluminium"))), 0.5);
  EXPECT_GT(*axialVariation(extractSlices(tableOf("satin-red-90"))),
            HalfwayParams{}.isotropyThreshold);
  ExtractionParams diagonalOnly;
  diagonalOnly.diagonalOnly = true;
  EXPECT_FALSE(axialVariation(extractSlices(tableOf("blue-plastic"), diagonalOnly)));
}

TEST(HalfwayMethod, KeepsTheMeasuredSubspacesAndReproducesADiffuseMaterial) {
  const SliceSet slices = extractSlices(tableOf("brushed-steel-30"));
  HalfwayReport report;
  const Abrdf result = reconstructHalfway(slices, {}, &report);
  EXPECT_FALSE(report.treatedIsotropic);
  for (const Subspace& s : reconstructMeasuredSubspaces(slices, false, {}, "test")) {
    for (int p = 0; p < s.lightRing().count; ++p) {
      for (int q = 0; q < s.viewRing().count; ++q) {
        const Rgb expected = s.at(p, q);
        const Rgb got = result.at(s.lightRing().index(p), s.viewRing().index(q));
        for (std::size_t c = 0; c < 3; ++c)
          EXPECT_NEAR(got[c], std::max(0.0, expected[c]), 1e-6);
      }
    }
  }
  // A Lambertian surface is all floor: exact on both paths.
  const Abrdf lambert = tableOf("matte-paint");
  HalfwayParams anisotropic;
  anisotropic.isotropyThreshold = -1.0;
  EXPECT_LT(test::maxAbsDifference(reconstructHalfway(extractSlices(lambert)), lambert), 1e-5);
  EXPECT_LT(
      test::maxAbsDifference(reconstructHalfway(extractSlices(lambert), anisotropic), lambert),
      1e-5);
}

TEST(HalfwayMethod, BeatsMethodBOnGlossyIsotropicAndAnisotropicMaterials) {
  // The unmeasured highlights (docs/method.md §7): Method B scales the 30 deg ring and blends
  // subspaces, the halfway neighbours carry the measured peaks over.
  for (const char* material : {"blue-plastic", "brushed-aluminium", "satin-blue-45"}) {
    const Abrdf truth = tableOf(material);
    const SliceSet slices = extractSlices(truth);
    const eval::Metrics halfway = eval::compare(truth, reconstructHalfway(slices));
    const eval::Metrics methodB = eval::compare(truth, reconstructMethodB(slices));
    EXPECT_LT(halfway.deltaE, 0.9 * methodB.deltaE) << material;
    EXPECT_LT(halfway.rmse, methodB.rmse) << material;
  }
}

TEST(HalfwayMethod, IsotropicModeNeedsOnlyTheDiagonalSlicesAndMissingSlicesAreNamed) {
  ExtractionParams diagonalOnly;
  diagonalOnly.diagonalOnly = true;
  const Abrdf truth = tableOf("red-plastic-ggx");
  const SliceSet slices = extractSlices(truth, diagonalOnly);
  EXPECT_THROW(reconstructHalfway(slices), ReconstructionError);
  HalfwayParams params;
  params.isotropic = true;
  HalfwayReport report;
  const eval::Metrics m = eval::compare(truth, reconstructHalfway(slices, params, &report));
  EXPECT_TRUE(report.treatedIsotropic);
  EXPECT_GT(m.psnrDb, 20.0);
}

TEST(HalfwayMethod, RejectsInvalidParams) {
  const SliceSet slices = extractSlices(tableOf("matte-paint"));
  HalfwayParams params;
  params.neighbours = 0;
  EXPECT_THROW(reconstructHalfway(slices, params), recon::ReconArgumentError);
  params = {};
  params.differenceWeight = -1.0;
  EXPECT_THROW(reconstructHalfway(slices, params), recon::ReconArgumentError);
}

}  // namespace
}  // namespace slicecap::recon
