// The uniform baseline's reconstruction: exact at the samples, constants, averaging, errors.
#include "slicecap/recon/scattered_rbf.hpp"

#include <gtest/gtest.h>

#include "../support/test_support.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/uniform_sampling.hpp"

namespace slicecap::recon {
namespace {

TEST(ScatteredRbf, ReproducesTheUniformSamples) {
  const Abrdf truth = models::tabulate(*models::findMaterial("satin-blue-45"));
  const Abrdf result = reconstructScattered(extractUniformSamples(truth, 13));
  for (int light : farthestPointDirections(13)) {
    for (int view : farthestPointDirections(13)) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(result.channel(light, view, c), truth.channel(light, view, c),
                    1e-5 * (1.0 + truth.channel(light, view, c)));
      }
    }
  }
}

TEST(ScatteredRbf, ReproducesAConstantTable) {
  const Abrdf truth = models::tabulate(*models::makeLambert({0.3, 0.5, 0.7}));
  EXPECT_LT(test::maxAbsDifference(reconstructScattered(extractUniformSamples(truth, 13)), truth),
            1e-6);
  ScatteredRbfParams gamma;
  gamma.rbf.valueGamma = 2.2;
  EXPECT_LT(
      test::maxAbsDifference(reconstructScattered(extractUniformSamples(truth, 13), gamma), truth),
      1e-6)
      << "the gamma round trip keeps a constant";
}

TEST(ScatteredRbf, AnInterpolantSingularInFloatingPointIsAnErrorNotAZeroTable) {
  const Abrdf truth = models::tabulate(*models::makeLambert({0.3, 0.5, 0.7}));
  ScatteredRbfParams params;
  params.rbf.kernel = RbfKernel::InverseMultiquadric;
  params.rbf.shapeScale = 1e-300;  // 1/0 on the diagonal: NaN, which was clipped to zeros
  EXPECT_THROW(reconstructScattered(extractUniformSamples(truth, 13), params), ReconstructionError);
}

TEST(ScatteredRbf, AveragesSamplesAtTheSameDirections) {
  SliceSet samples;
  samples.add({SliceKind::Point, {30, 30}}, {{30, 0}, {30, 180}, Rgb::gray(1.0)});
  samples.add({SliceKind::Point, {30, 30}}, {{30, 0}, {30, 180}, Rgb::gray(3.0)});
  const Abrdf result = reconstructScattered(samples);
  EXPECT_NEAR(result.at(bonn::indexOf({30, 0}), bonn::indexOf({30, 180})).r(), 2.0, 1e-9);
  EXPECT_NEAR(result.at(0, 0).g(), 2.0, 1e-9) << "one centre: the constant";
}

TEST(ScatteredRbf, RejectsAnEmptySet) {
  EXPECT_THROW(reconstructScattered(SliceSet{}), ReconstructionError);
}

}  // namespace
}  // namespace slicecap::recon
