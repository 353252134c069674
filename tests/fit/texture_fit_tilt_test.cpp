// The texture fit's shading-normal tilt (fit::fitTexture, docs/material-fit.md "The normal map"):
// texels tabulated from known GGX materials under known tilts, the tilt applied by turning the
// light and view into the tilted frame by hand (not through the fit's tilted lobe), recovered
// within 1 deg; a flat tile stays flat; a texel with no specular lobe is reported flat as
// undetermined.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>

#include "../support/tilted_table.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/fit/texture_fit.hpp"

namespace slicecap::fit {
namespace {

using test::tilt::angleDeg;
using test::tilt::tabulateTilted;
using test::tilt::tiltedNormal;
using test::tilt::Vec;

constexpr int kSize = 3;

// Texel (x, y): alphas 0.1 to 0.3, brushed at 30 deg, tilted up to 20 deg in varied azimuths
// (neighbours differ by 5 to 10 deg, so the warm start has a tilt to move).
FittedMaterial materialAt(int x, int y) {
  FittedMaterial m;
  m.diffuseAlbedo = {0.2 + 0.1 * x, 0.25, 0.3 - 0.05 * y};
  m.specularF0 = Rgb::gray(0.04 + 0.2 * ((x + y) % 2));
  m.alphaBitangent = 0.1 + 0.05 * y;
  m.alphaTangent = std::min(0.3, 2.0 * m.alphaBitangent);
  m.tangentDeg = 30.0;
  // Column 1 is given the other way round (the larger alpha across the tangent): its canonical
  // form under the tilt is not the untilted azimuth + 90 deg.
  if (x == 1) std::swap(m.alphaTangent, m.alphaBitangent);
  return m;
}
Vec normalAt(int x, int y) {
  return tiltedNormal(5.0 + 7.5 * x, 40.0 + 100.0 * y);
}

TexelRowReader readerOf(const std::vector<Abrdf>& tables) {
  return [&tables](int row, std::vector<Abrdf>& out) {
    out.assign(tables.begin() + row * kSize, tables.begin() + (row + 1) * kSize);
  };
}

TEST(TextureFitTilt, RecoversEachTexelsTiltWithinOneDegree) {
  std::vector<Abrdf> tables;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      tables.push_back(tabulateTilted(materialAt(x, y), normalAt(x, y)));
  const TextureFitResult result = fitTexture(kSize, readerOf(tables));
  EXPECT_EQ(result.tiltFitted, tables.size());
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const TexelFit& texel = result.texels[std::size_t(y * kSize + x)];
      const FittedMaterial truth = materialAt(x, y).canonical();
      SCOPED_TRACE("texel (" + std::to_string(x) + "," + std::to_string(y) + ")");
      ASSERT_EQ(texel.status, TexelStatus::Fitted) << texel.problem;
      EXPECT_EQ(texel.tilt, TiltStatus::Fitted);
      EXPECT_LE(angleDeg(texel.shadingNormal, normalAt(x, y)), 1.0);
      EXPECT_NEAR(texel.material.alphaTangent / truth.alphaTangent, 1.0, 0.05);
      EXPECT_NEAR(texel.material.alphaBitangent / truth.alphaBitangent, 1.0, 0.05);
      if (x != 1) {  // (column 1's canonical tangent under the tilt: the table check below)
        EXPECT_LE(std::abs(tangentDifferenceDeg(texel.material.tangentDeg, truth.tangentDeg)), 1.0);
      }
      EXPECT_LE(texel.rmseLevels, 0.5);
      // The reported material and normal, tabulated the independent way, are the texel's table.
      const UnitVector& n = texel.shadingNormal;
      EXPECT_LE(eval::compare(tables[std::size_t(y * kSize + x)],
                              tabulateTilted(texel.material, {n.x, n.y, n.z}))
                    .deltaE,
                0.1);
    }
}

TEST(TextureFitTilt, FlatTileStaysFlat) {
  std::vector<Abrdf> tables;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      tables.push_back(tabulate(materialAt(x, y)));
  const TextureFitResult result = fitTexture(kSize, readerOf(tables));
  for (const TexelFit& texel : result.texels) {
    ASSERT_EQ(texel.status, TexelStatus::Fitted) << texel.problem;
    EXPECT_EQ(texel.tilt, TiltStatus::Fitted);
    EXPECT_LE(angleDeg(texel.shadingNormal, {0.0, 0.0, 1.0}), 0.5);
  }
}

TEST(TextureFitTilt, DiffuseOnlyTexelIsFlatAsUndetermined) {
  std::vector<Abrdf> tables;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      tables.push_back(tabulateTilted(materialAt(x, y), normalAt(x, y)));
  // Texel (1,1): a tilted matte paint, no specular lobe at all.
  FittedMaterial matte = materialAt(1, 1);
  matte.specularF0 = Rgb{};
  matte.specularF90 = 0.0;
  tables[4] = tabulateTilted(matte, normalAt(1, 1));
  const TextureFitResult result = fitTexture(kSize, readerOf(tables));
  const TexelFit& texel = result.texels[4];
  ASSERT_EQ(texel.status, TexelStatus::Fitted) << texel.problem;
  EXPECT_EQ(texel.tilt, TiltStatus::NoLobe);
  EXPECT_EQ(toString(texel.tilt), "flat: no specular lobe to tilt");
  EXPECT_EQ(texel.shadingNormal.z, 1.0);
  EXPECT_EQ(result.tiltFitted, tables.size() - 1);
  // Its neighbours, warm-started from it, still find their tilts.
  EXPECT_EQ(result.texels[5].tilt, TiltStatus::Fitted);
  EXPECT_LE(angleDeg(result.texels[5].shadingNormal, normalAt(2, 1)), 1.0);
}

TEST(TextureFitTilt, RoughLobeReachingTheTiltedHorizonIsRecovered) {
  // Alphas 0.37 / 0.25 tilted 15 deg toward +y and 9.6 toward +x: the grid's 75 deg views on the
  // far side lie at the tilted horizon, where the model jumps to zero; the fit must not be pinned
  // there.
  FittedMaterial rough;
  rough.diffuseAlbedo = {0.1, 0.15, 0.4};
  rough.specularF0 = Rgb::gray(0.12);
  rough.alphaTangent = 0.37;
  rough.alphaBitangent = 0.247;
  rough.tangentDeg = 120.0;
  const Vec normal = test::tilt::unit(
      {std::tan(9.6 * std::numbers::pi / 180), std::tan(15.0 * std::numbers::pi / 180), 1.0});
  const std::vector<Abrdf> tables{tabulateTilted(rough, normal)};
  const TextureFitResult result =
      fitTexture(1, [&tables](int, std::vector<Abrdf>& out) { out = tables; });
  const TexelFit& texel = result.texels[0];
  ASSERT_EQ(texel.status, TexelStatus::Fitted) << texel.problem;
  EXPECT_LE(texel.rmseLevels, 0.5);
  EXPECT_LE(angleDeg(texel.shadingNormal, normal), 1.0);
  EXPECT_NEAR(texel.material.alphaTangent / rough.alphaTangent, 1.0, 0.02);
  EXPECT_NEAR(texel.material.specularF90, 1.0, 0.02);
}

}  // namespace
}  // namespace slicecap::fit
