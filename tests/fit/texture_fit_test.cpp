// The texture fit (fit::fitTexture) on a simulated BTF whose texels have known GGX parameters:
// each texel's roughness and tangent recovered, a tangent jump between neighbours still found (the
// multi-start fallback), and texels with no samples or that are not BRDFs named, never fitted.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/fit/argument_error.hpp"
#include "slicecap/fit/texture_fit.hpp"

namespace slicecap::fit {
namespace {

constexpr int kSize = 4;

// Texel (x, y): roughness grows with x; the top two rows are brushed at 20 deg, the bottom two at
// 110 deg (a woven-like jump between neighbours a warm start cannot bridge); colours vary.
FittedMaterial truthAt(int x, int y) {
  FittedMaterial m;
  m.diffuseAlbedo = {0.15 + 0.1 * x, 0.2, 0.35 - 0.05 * y};
  m.specularF0 = Rgb::gray(0.04 + 0.1 * (y % 2));
  m.alphaBitangent = 0.06 + 0.03 * x;
  m.alphaTangent = 3.0 * m.alphaBitangent;
  m.tangentDeg = y < 2 ? 20.0 : 110.0;
  return m.canonical();
}

std::vector<Abrdf> truthTables() {
  std::vector<Abrdf> tables;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) tables.push_back(tabulate(truthAt(x, y)));
  return tables;
}

TexelRowReader readerOf(const std::vector<Abrdf>& tables) {
  return [&tables](int row, std::vector<Abrdf>& out) {
    out.assign(tables.begin() + row * kSize, tables.begin() + (row + 1) * kSize);
  };
}

TEST(TextureFit, RecoversEveryTexelsGgxParameters) {
  const std::vector<Abrdf> tables = truthTables();
  const TextureFitResult result = fitTexture(kSize, readerOf(tables));
  ASSERT_EQ(result.texels.size(), tables.size());
  EXPECT_EQ(result.fitted, tables.size());
  // Texel (0,0) has no neighbour to start from. (The jump between rows 1 and 2 is bridged by the
  // warm start itself on exact tables: the alphas swap.)
  EXPECT_GE(result.multiStart, 1u);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const std::size_t i = std::size_t(y * kSize + x);
      const TexelFit& texel = result.texels[i];
      const FittedMaterial truth = truthAt(x, y);
      SCOPED_TRACE("texel (" + std::to_string(x) + "," + std::to_string(y) + ")");
      ASSERT_EQ(texel.status, TexelStatus::Fitted) << texel.problem;
      EXPECT_NEAR(texel.material.alphaTangent / truth.alphaTangent, 1.0, 0.05);
      EXPECT_NEAR(texel.material.alphaBitangent / truth.alphaBitangent, 1.0, 0.05);
      EXPECT_LE(std::abs(tangentDifferenceDeg(texel.material.tangentDeg, truth.tangentDeg)), 2.0);
      EXPECT_LE(eval::compare(tables[i], tabulate(texel.material)).deltaE, 1.0);
    }
}

TEST(TextureFit, NamesTexelsWithNoSamplesOrThatAreNotBrdfs) {
  std::vector<Abrdf> tables = truthTables();
  tables[1] = Abrdf{};                        // texel (1,0): nothing reconstructed
  tables[6].channel(40, 3, 2) = -0.25f;       // texel (2,1)
  tables[11].channel(0, 0, 0) = std::nanf(""); // texel (3,2)
  const TextureFitResult result = fitTexture(kSize, readerOf(tables), {.threads = 2});
  EXPECT_EQ(result.fitted, tables.size() - 3);
  EXPECT_EQ(result.texels[1].status, TexelStatus::NoSamples);
  EXPECT_NE(result.texels[1].problem.find("texel (1,0): no samples"), std::string::npos)
      << result.texels[1].problem;
  EXPECT_EQ(result.texels[6].status, TexelStatus::NotABrdf);
  EXPECT_NE(result.texels[6].problem.find("texel (2,1): not a BRDF: value -0.25 at light 40, view 3, "
                                          "channel B"),
            std::string::npos)
      << result.texels[6].problem;
  EXPECT_EQ(result.texels[11].status, TexelStatus::NotABrdf);
  EXPECT_NE(result.texels[11].problem.find("texel (3,2)"), std::string::npos);
  // The texel after a bad one still starts from a good solution and is fitted.
  EXPECT_EQ(result.texels[2].status, TexelStatus::Fitted);
  EXPECT_NEAR(result.texels[2].material.alphaBitangent / truthAt(2, 0).alphaBitangent, 1.0, 0.05);
}

TEST(TextureFit, NamesTexelsWhoseFitDidNotConverge) {
  const std::vector<Abrdf> tables = truthTables();
  const TextureFitResult result = fitTexture(kSize, readerOf(tables), {.maxIterations = 1});
  EXPECT_LT(result.fitted, tables.size());
  const TexelFit& first = result.texels[0];
  EXPECT_EQ(first.status, TexelStatus::NotConverged);
  EXPECT_NE(first.problem.find("texel (0,0): the GGX fit did not converge"), std::string::npos)
      << first.problem;
}

TEST(TextureFit, PassesOnARowThatCannotBeRead) {
  const std::vector<Abrdf> tables = truthTables();
  const TexelRowReader failing = [&tables](int row, std::vector<Abrdf>& out) {
    if (row == 2) {
      // Slow, so that the other thread takes row 3 and waits for this row's first texel.
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      throw std::runtime_error("btf/tv000_pv000/x.exr: truncated");
    }
    out.assign(tables.begin() + row * kSize, tables.begin() + (row + 1) * kSize);
  };
  // Row 3 waits for the first texel of row 2: the failure must release it, not hang.
  EXPECT_THROW(fitTexture(kSize, failing, {.threads = 2}), std::runtime_error);
}

TEST(TextureFit, RefusesBadOptions) {
  const std::vector<Abrdf> tables = truthTables();
  EXPECT_THROW(fitTexture(0, readerOf(tables)), fit::FitArgumentError);
  EXPECT_THROW(fitTexture(kSize, readerOf(tables), {.threads = 0}), fit::FitArgumentError);
  // A stride that is a multiple of 3 would see a third of the view directions only.
  EXPECT_THROW(fitTexture(kSize, readerOf(tables), {.pairStride = 3}), fit::FitArgumentError);
}

}  // namespace
}  // namespace slicecap::fit
