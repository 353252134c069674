// The paper's metrics: encoding, dE anchors, identities and sensitivity to the right things.
#include "slicecap/eval/metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slicecap/eval/eval_error.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::eval {
namespace {

TEST(Metrics, IdenticalTablesHaveNoError) {
  const Abrdf t = models::tabulate(*models::findMaterial("blue-plastic"));
  const Metrics m = compare(t, t);
  EXPECT_EQ(m.deltaE, 0.0);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_EQ(m.psnrDb, kMaxPsnrDb);
  EXPECT_EQ(m.relativeRmse, 0.0);
}

TEST(Metrics, SrgbTransferFunctionsAreInverse) {
  for (double x = 0.0; x <= 1.0; x += 0.01)
    EXPECT_NEAR(srgbDecode(srgbEncode(x)), x, 1e-12);
  EXPECT_NEAR(srgbEncode(0.18), 0.4613561, 1e-6);
}

TEST(Metrics, DeltaEAnchors) {
  EXPECT_NEAR(deltaE76({0, 0, 0}, {255, 255, 255}), 100.0, 1e-6);
  EXPECT_NEAR(deltaE76({128, 128, 128}, {128, 128, 128}), 0.0, 1e-12);
  EXPECT_GT(deltaE76({255, 0, 0}, {0, 255, 0}), 100.0);
}

TEST(Metrics, EncodingIsCosWeightedAndReferenceNormalised) {
  Abrdf t;
  t.set(0, 0, Rgb::gray(2.0));   // theta_i 0: weight 1, the maximum
  t.set(57, 0, Rgb::gray(2.0));  // theta_i 75: weight cos 75
  const double maximum = cosWeightedMaximum(t);
  EXPECT_DOUBLE_EQ(maximum, 2.0);
  const auto encoded = encodePaper8Bit(t, maximum);
  EXPECT_EQ(encoded[0], 255);
  EXPECT_EQ(encoded[57 * 81 * 3],
            std::lround(srgbEncode(std::cos(75.0 * std::numbers::pi / 180)) * 255));
  EXPECT_EQ(encoded[3], 0);
}

TEST(Metrics, ScalingTheTestChangesTheErrorButNotTheReferenceScale) {
  const Abrdf ref = models::tabulate(*models::findMaterial("red-plastic-ggx"));
  Abrdf brighter = ref;
  for (float& v : brighter.values())
    v *= 1.2f;
  const Metrics m = compare(ref, brighter);
  EXPECT_GT(m.rmse, 1.0);
  EXPECT_GT(m.deltaE, 0.5);
  EXPECT_NEAR(m.relativeRmse, 0.2, 1e-6);
  EXPECT_NEAR(m.peakRatio, 1.2, 1e-6);
  EXPECT_NEAR(m.psnrDb, 20 * std::log10(255 / m.rmse), 1e-9);
  // The metrics are invariant to a common scale of reference and test (normalised by the
  // reference).
  Abrdf ref2 = ref, brighter2 = brighter;
  for (float& v : ref2.values())
    v *= 4.0f;
  for (float& v : brighter2.values())
    v *= 4.0f;
  EXPECT_NEAR(compare(ref2, brighter2).rmse, m.rmse, 1e-9);
}

TEST(Metrics, PeakRatioShowsAHighlightLostToClipping) {
  const Abrdf ref = models::tabulate(*models::findMaterial("brushed-aluminium"));
  EXPECT_DOUBLE_EQ(compare(ref, ref).peakRatio, 1.0);
  // Every value above a tenth of the peak clipped to it: the lobe's top is gone.
  Abrdf clipped = ref;
  const float peak = *std::max_element(ref.values().begin(), ref.values().end());
  for (float& v : clipped.values())
    v = std::min(v, peak / 10.0f);
  const Metrics m = compare(ref, clipped);
  EXPECT_NEAR(m.peakRatio, 0.1, 1e-6);
  EXPECT_GT(m.relativeRmse, 0.3);
}

TEST(Metrics, RejectsABlackReference) {
  EXPECT_THROW(compare(Abrdf(), Abrdf()), eval::EvalError);
}

}  // namespace
}  // namespace slicecap::eval
