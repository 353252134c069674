// Method A: the shared system's shape, kept measured subspaces, constants, float evaluation.
#include "slicecap/recon/method_a.hpp"

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

// One test per process builds the shared system (~0.2 s), so related checks share a test.
TEST(MethodA, SharedSystemKeepsTheMeasuredSubspacesAndIsExactForConstantsAtAnyGamma) {
  const MethodASystem& system = sharedMethodASystem();
  EXPECT_EQ(system.centreEntries().size(), 1296u);
  EXPECT_EQ(system.otherEntries().size(), 6561u - 1296u);
  // docs/method.md §5.2: r0 ~ 0.26 rad on the Bonn grid.
  EXPECT_NEAR(system.interpolant().shapeRad(), 0.26, 0.01);
  EXPECT_EQ(&system, &sharedMethodASystem()) << "built once";
  EXPECT_LT(system.memoryBytes(), std::size_t{45} << 20);

  const SliceSet slices = extractSlices(tableOf("brushed-steel-30"));
  const Abrdf result = reconstructMethodA(slices);
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
  const Abrdf lambert = tableOf("matte-paint");
  EXPECT_LT(test::maxAbsDifference(reconstructMethodA(extractSlices(lambert)), lambert), 1e-5);

  // The value gamma uses the same system, so it is checked here. v^(1/gamma) of a constant is a
  // constant: exact again. On a glossy material the compressed highlights overshoot less between 30
  // and 75 deg (the paper interpolated sRGB data).
  MethodAParams gamma;
  gamma.rbf.valueGamma = 2.2;
  EXPECT_LT(test::maxAbsDifference(reconstructMethodA(extractSlices(lambert), gamma), lambert),
            1e-5);
  const Abrdf glossy = tableOf("blue-plastic");
  const SliceSet glossySlices = extractSlices(glossy);
  EXPECT_LT(eval::compare(glossy, reconstructMethodA(glossySlices, gamma)).rmse,
            eval::compare(glossy, reconstructMethodA(glossySlices)).rmse);
  gamma.rbf.valueGamma = 0.0;
  EXPECT_THROW(reconstructMethodA(glossySlices, gamma), recon::ReconArgumentError);
  EXPECT_DOUBLE_EQ(fromInterpolatedValue(toInterpolatedValue(0.3, 2.2), 2.2), 0.3);
  EXPECT_EQ(toInterpolatedValue(-1.0, 2.2), 0.0) << "negatives clipped";
}

TEST(MethodA, AnInterpolantSingularInFloatingPointIsAnErrorNotAZeroTable) {
  // The inverse multiquadric with r0 -> 0 puts 1/0 on the diagonal: NaN everywhere, which the
  // clipping of negatives turned into an all-zero interpolation, silently.
  MethodAParams params;
  params.rbf.kernel = RbfKernel::InverseMultiquadric;
  params.rbf.shapeScale = 1e-300;
  EXPECT_THROW(reconstructMethodA(extractSlices(tableOf("matte-paint")), params),
               ReconstructionError);
}

TEST(MethodA, FloatEvaluationStaysWithinItsStatedBound) {
  // The float evaluation matrix against the double interpolant at every 7th other entry, on a
  // sharp brushed metal (values up to ~100 1/sr).
  const Abrdf truth = tableOf("brushed-aluminium");
  const MethodASystem& system = sharedMethodASystem();
  const std::vector<Subspace> measured =
      reconstructMeasuredSubspaces(extractSlices(truth), false, {}, "test");
  const Abrdf result = system.interpolate(measured);
  Eigen::MatrixXd values(1296, 3);
  for (std::size_t i = 0; i < 1296; ++i) {
    const TableEntry e = system.centreEntries()[i];
    for (int c = 0; c < 3; ++c)
      values(Eigen::Index(i), c) = result.channel(e.light, e.view, c);
  }
  const Eigen::MatrixXd coefficients = system.interpolant().coefficients(values);
  const double peak = *std::max_element(truth.values().begin(), truth.values().end());
  for (std::size_t j = 0; j < system.otherEntries().size(); j += 7) {
    const TableEntry e = system.otherEntries()[j];
    const FeaturePoint x =
        onionFeatures(bonn::direction(e.light), bonn::direction(e.view), system.frame());
    for (int c = 0; c < 3; ++c) {
      const double exact = std::max(0.0, system.interpolant().evaluate(coefficients.col(c), x));
      EXPECT_NEAR(result.channel(e.light, e.view, c), exact, 5e-5 * peak);
    }
  }
}

TEST(MethodA, IsotropicModeNeedsOnlyTheDiagonalSlices) {
  recon::ExtractionParams diagonalOnly;
  diagonalOnly.diagonalOnly = true;
  const Abrdf truth = tableOf("blue-plastic");
  const SliceSet slices = extractSlices(truth, diagonalOnly);
  EXPECT_THROW(reconstructMethodA(slices), ReconstructionError);
  MethodAParams params;
  params.isotropic = true;
  const eval::Metrics m = eval::compare(truth, reconstructMethodA(slices, params));
  EXPECT_GT(m.psnrDb, 20.0);
}

TEST(MethodA, NamesEveryMissingSlice) {
  SliceSet slices = extractSlices(tableOf("satin-red-90"));
  SliceSet partial;
  for (const Slice& s : slices.slices()) {
    if (s.id.elevations != ElevationPair{75, 30}) {
      for (const SliceSample& sample : s.samples)
        partial.add(s.id, sample);
    }
  }
  try {
    reconstructMethodA(partial);
    FAIL() << "no error";
  } catch (const ReconstructionError& e) {
    EXPECT_NE(std::string(e.what()).find("axial 75/30, diagonal 75/30"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace slicecap::recon
