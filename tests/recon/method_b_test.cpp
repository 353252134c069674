// Method B end to end on analytic tables: exactness on its own model, isotropy, capture realism.
#include "slicecap/recon/method_b.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../support/test_support.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::recon {
namespace {

TEST(MethodB, ReconstructsAnElevationLobeTableAlmostExactly) {
  // f = k (cos_i cos_v)^n is the model Method B assumes: every elevation, measured or not, and the
  // extrapolated 0 and 15 deg rings must come back.
  const auto model = models::makeElevationLobe({0.30, 0.20, 0.10}, 0.8);
  const Abrdf truth = models::tabulate(*model);
  MethodBReport report;
  const Abrdf result = reconstructMethodB(extractSlices(truth), {}, &report);
  EXPECT_TRUE(report.allConverged());
  EXPECT_EQ(report.fits.size(), 8u) << "2 view lines and 6 light lines";
  EXPECT_LT(eval::compare(truth, result).relativeRmse, 1e-5);
  EXPECT_LT(test::maxAbsDifference(truth, result), 1e-6);
}

TEST(MethodB, CeresFitsAgreeWithTheClosedForm) {
  const auto ward = models::findMaterial("brushed-steel-30");
  MethodBReport report;
  reconstructMethodB(extractSlices(models::tabulate(*ward)), {}, &report);
  ASSERT_TRUE(report.allConverged());
  for (const LineFit& f : report.fits) {
    EXPECT_FALSE(f.usedClosedForm) << f.line;
    EXPECT_TRUE(std::isfinite(f.fit.lobe.n)) << f.line;
  }
}

TEST(MethodB, IsotropicModeMatchesTheFullMethodOnIsotropicMaterials) {
  const auto model = models::makeBlinnPhong({0.1, 0.2, 0.3}, {0.5, 0.5, 0.5}, 20.0);
  const SliceSet slices = extractSlices(models::tabulate(*model));
  MethodBParams isotropic;
  isotropic.isotropic = true;
  const Abrdf full = reconstructMethodB(slices);
  const Abrdf diagonalOnly = reconstructMethodB(slices, isotropic);
  // Different slice means drive the lobes (the axial samples count in the full method), so the
  // unmeasured elevations differ slightly; the measured pairs agree exactly.
  EXPECT_LT(eval::compare(full, diagonalOnly).relativeRmse, 0.05);
  for (int p = 0; p < 24; ++p) {
    for (int q = 0; q < 24; ++q) {
      EXPECT_NEAR(full.channel(57 + p, 57 + q, 1), diagonalOnly.channel(57 + p, 57 + q, 1), 1e-5);
    }
  }
}

TEST(MethodB, KeepsTheSliceSumSubspacesAtTheMeasuredPairs) {
  const auto ward = models::findMaterial("satin-red-90");
  const SliceSet slices = extractSlices(models::tabulate(*ward));
  const Abrdf result = reconstructMethodB(slices);
  for (ElevationPair pair : kMeasuredPairs) {
    const Subspace expected = reconstructSubspace(*slices.find({SliceKind::Axial, pair}),
                                                  *slices.find({SliceKind::Diagonal, pair}));
    const Subspace got = Subspace::fromTable(result, pair);
    for (int p = 0; p < got.lightRing().count; ++p) {
      for (int q = 0; q < got.viewRing().count; ++q) {
        EXPECT_NEAR(got.at(p, q).r(), std::max(0.0, expected.at(p, q).r()), 1e-6);
      }
    }
  }
}

TEST(MethodB, NamesEveryMissingSlice) {
  const auto model = models::findMaterial("matte-paint");
  const SliceSet all = extractSlices(models::tabulate(*model));
  SliceSet partial;
  for (const Slice& s : all.slices()) {
    if (s.id == SliceId{SliceKind::Axial, {30, 75}} ||
        s.id == SliceId{SliceKind::Diagonal, {75, 30}})
      continue;
    for (const SliceSample& sample : s.samples)
      partial.add(s.id, sample);
  }
  try {
    reconstructMethodB(partial);
    FAIL() << "expected ReconstructionError";
  } catch (const ReconstructionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("axial 30/75"), std::string::npos) << what;
    EXPECT_NE(what.find("diagonal 75/30"), std::string::npos) << what;
  }
  MethodBParams isotropic;
  isotropic.isotropic = true;
  EXPECT_THROW(reconstructMethodB(partial, isotropic), ReconstructionError)
      << "diagonal 75/30 is still missing";
}

TEST(MethodB, HandlesAJitteredCaptureWithMissingSamples) {
  // A real sweep: ~15 deg steps with jitter, angles off nominal by up to 3 deg, 10 % of bins empty.
  const auto model = models::findMaterial("brushed-aluminium");
  const Abrdf truth = models::tabulate(*model);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-3.0, 3.0), unit(0.0, 1.0);
  SliceSet capture;
  for (ElevationPair pair : kMeasuredPairs) {
    for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
      for (int k = 0; k < 24; ++k) {
        if (unit(rng) < 0.1) continue;
        const AzimuthPair at = slicePoint(kind, k * 15.0 + jitter(rng));
        const Direction light{pair.thetaIDeg + jitter(rng), at.phiIDeg};
        const Direction view{pair.thetaVDeg + jitter(rng), at.phiVDeg};
        capture.add({kind, pair},
                    {light, view, model->evaluate(toUnitVector(light), toUnitVector(view))});
      }
    }
  }
  MethodBReport report;
  const Abrdf fromCapture = reconstructMethodB(capture, {}, &report);
  EXPECT_TRUE(report.allConverged());
  const Abrdf fromIdeal = reconstructMethodB(extractSlices(truth));
  const eval::Metrics capturedError = eval::compare(truth, fromCapture);
  const eval::Metrics idealError = eval::compare(truth, fromIdeal);
  EXPECT_LT(capturedError.deltaE, idealError.deltaE * 1.25 + 0.5)
      << "captured " << capturedError.deltaE << " vs ideal " << idealError.deltaE;
}

TEST(MethodB, NeverReturnsNegativeValues) {
  const auto model = models::findMaterial("satin-blue-45");
  SliceSet slices = extractSlices(models::tabulate(*model));
  SliceSet noisy;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (const Slice& s : slices.slices()) {
    for (SliceSample sample : s.samples) {
      for (std::size_t c = 0; c < 3; ++c)
        sample.value[c] += noise(rng);  // dark noise can go below 0
      noisy.add(s.id, sample);
    }
  }
  const Abrdf result = reconstructMethodB(noisy);
  for (float v : result.values())
    ASSERT_GE(v, 0.0f);
}

}  // namespace
}  // namespace slicecap::recon
