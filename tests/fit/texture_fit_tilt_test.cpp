// The texture fit's shading-normal tilt (fit::fitTexture, docs/material-fit.md "The normal map"):
// texels tabulated from known GGX materials under known tilts, the tilt applied by turning the
// light and view into the tilted frame by hand (not through the fit's tilted lobe), recovered
// within 1 deg; a flat tile stays flat; a texel with no specular lobe is reported flat as
// undetermined.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slicecap/fit/texture_fit.hpp"

namespace slicecap::fit {
namespace {

constexpr int kSize = 3;

struct Vec {
  double x, y, z;
};
double dot(const Vec& a, const Vec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec unit(const Vec& a) {
  const double n = std::sqrt(dot(a, a));
  return {a.x / n, a.y / n, a.z / n};
}
Vec cross(const Vec& a, const Vec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The normal tilted by `tiltDeg` toward azimuth `azimuthDeg`.
Vec tiltedNormal(double tiltDeg, double azimuthDeg) {
  const double t = tiltDeg * std::numbers::pi / 180.0, a = azimuthDeg * std::numbers::pi / 180.0;
  return {std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t)};
}

// The BRDF f_eff with f eff cos_i = f' cos_i': `flat` (its tangent at `flat.tangentDeg` in the
// untilted plane) evaluated with light and view written in the frame of `normal`, whose tangent
// is the untilted tangent with its component along `normal` removed. Zero behind the tilted
// surface.
Abrdf tabulateTilted(FittedMaterial flat, const Vec& normal) {
  const double t = flat.tangentDeg * std::numbers::pi / 180.0;
  const Vec untilted{std::cos(t), std::sin(t), 0.0};
  const double along = dot(untilted, normal);
  const Vec tangent = unit({untilted.x - along * normal.x, untilted.y - along * normal.y,
                            untilted.z - along * normal.z});
  const Vec bitangent = cross(normal, tangent);
  flat.tangentDeg = 0.0;  // in the tilted frame the tangent is x
  return tabulateOnGrid([&](const UnitVector& l, const UnitVector& v) {
    const Vec lw{l.x, l.y, l.z}, vw{v.x, v.y, v.z};
    const UnitVector lt{dot(lw, tangent), dot(lw, bitangent), dot(lw, normal)};
    const UnitVector vt{dot(vw, tangent), dot(vw, bitangent), dot(vw, normal)};
    if (lt.z <= 0.0 || vt.z <= 0.0) return Rgb{};
    Rgb value = flat.evaluate(lt, vt);
    for (std::size_t c = 0; c < 3; ++c) value[c] *= lt.z / l.z;
    return value;
  });
}

// Texel (x, y): alphas 0.1 to 0.3, brushed at 30 deg, tilted up to 20 deg in varied azimuths
// (neighbours differ by 5 to 10 deg, so the warm start has a tilt to move).
FittedMaterial materialAt(int x, int y) {
  FittedMaterial m;
  m.diffuseAlbedo = {0.2 + 0.1 * x, 0.25, 0.3 - 0.05 * y};
  m.specularF0 = Rgb::gray(0.04 + 0.2 * ((x + y) % 2));
  m.alphaBitangent = 0.1 + 0.05 * y;
  m.alphaTangent = std::min(0.3, 2.0 * m.alphaBitangent) + 0.0 * x;
  m.tangentDeg = 30.0;
  return m;
}
Vec normalAt(int x, int y) { return tiltedNormal(5.0 + 7.5 * x, 40.0 + 100.0 * y); }

TexelRowReader readerOf(const std::vector<Abrdf>& tables) {
  return [&tables](int row, std::vector<Abrdf>& out) {
    out.assign(tables.begin() + row * kSize, tables.begin() + (row + 1) * kSize);
  };
}

double angleDeg(const UnitVector& a, const Vec& b) {
  return std::acos(std::clamp(dot({a.x, a.y, a.z}, b), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

TEST(TextureFitTilt, RecoversEachTexelsTiltWithinOneDegree) {
  std::vector<Abrdf> tables;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) tables.push_back(tabulateTilted(materialAt(x, y), normalAt(x, y)));
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
      EXPECT_NEAR(texel.material.alphaBitangent / truth.alphaBitangent, 1.0, 0.05);
      EXPECT_LE(std::abs(tangentDifferenceDeg(texel.material.tangentDeg, truth.tangentDeg)), 2.0);
      EXPECT_LE(texel.rmseLevels, 0.5);
    }
}

TEST(TextureFitTilt, FlatTileStaysFlat) {
  std::vector<Abrdf> tables;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) tables.push_back(tabulate(materialAt(x, y)));
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
    for (int x = 0; x < kSize; ++x) tables.push_back(tabulateTilted(materialAt(x, y), normalAt(x, y)));
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

}  // namespace
}  // namespace slicecap::fit
