// The glTF mapping: the KHR_materials_anisotropy/specular/ior BRDF evaluated as its specification
// writes it equals the fitted lobe where the extensions can say it, and losses are named where not.
#include "slicecap/material_export/gltf_material.hpp"

#include "slicecap/material_export/gltf_brdf.hpp"
#include "slicecap/material_export/gltf_writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace slicecap::material_export {
namespace {

struct V3 {
  double x, y, z;
};
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 normalise(V3 a) {
  const double l = std::sqrt(dot(a, a));
  return {a.x / l, a.y / l, a.z / l};
}

// The specular term as KHR_materials_anisotropy's README writes it (BRDF_specularAnisotropicGGX,
// D_GGX_anisotropic, V_GGX_anisotropic), with KHR_materials_specular + KHR_materials_ior's F0/F90,
// in the frame tangent = x, bitangent = y, normal = z; glTF's f_specular carries no cos.
Rgb gltfSpecular(const GltfMaterial& g, V3 l, V3 v) {
  const V3 n{0, 0, 1}, h = normalise({l.x + v.x, l.y + v.y, l.z + v.z});
  const V3 t{std::cos(g.anisotropyRotationRad), std::sin(g.anisotropyRotationRad), 0.0};
  const V3 b{-t.y, t.x, 0.0};  // cross(n, t)
  const double alpha = g.roughnessFactor * g.roughnessFactor;
  const double s2 = g.anisotropyStrength * g.anisotropyStrength;
  const double at = alpha * (1.0 - s2) + s2, ab = alpha;
  const double a2 = at * ab;
  const V3 f{ab * dot(t, h), at * dot(b, h), a2 * dot(n, h)};
  const double w2 = a2 / dot(f, f);
  const double d = a2 * w2 * w2 / std::numbers::pi;
  const double ggxV = dot(n, l) * std::sqrt(std::pow(at * dot(t, v), 2) + std::pow(ab * dot(b, v), 2) +
                                            std::pow(dot(n, v), 2));
  const double ggxL = dot(n, v) * std::sqrt(std::pow(at * dot(t, l), 2) + std::pow(ab * dot(b, l), 2) +
                                            std::pow(dot(n, l), 2));
  // The README's sample code also clamps V to [0, 1]; that clamp is a renderer's guard (it bites
  // only toward grazing, where 4 cos_i cos_v < G2), not part of the material's definition, so it is
  // left out here and noted in docs/material-export.md.
  const double vis = 0.5 / (ggxV + ggxL);
  const double iorF0 = std::pow((g.ior - 1.0) / (g.ior + 1.0), 2);
  const double weight = std::pow(1.0 - dot(v, h), 5);
  Rgb out;
  for (std::size_t c = 0; c < 3; ++c) {
    const double f0 = std::min(iorF0 * g.specularColorFactor[c], 1.0) * g.specularFactor;
    const double fr = f0 + (g.specularFactor - f0) * weight;
    out[c] = fr * vis * d;
  }
  return out;
}

V3 direction(double thetaDeg, double phiDeg) {
  const double t = thetaDeg * std::numbers::pi / 180.0, p = phiDeg * std::numbers::pi / 180.0;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

fit::FittedMaterial brushedMetal() {
  fit::FittedMaterial m;
  m.diffuseAlbedo = Rgb{};  // specular only: glTF's diffuse layering plays no part
  m.specularF0 = Rgb{0.55, 0.35, 0.2};
  m.specularF90 = 0.9;
  m.alphaTangent = 0.45;
  m.alphaBitangent = 0.08;
  m.tangentDeg = 30.0;
  return m;
}

// The largest relative difference of `actual(l, v)` from the fitted material's BRDF over 256
// light/view pairs spread over the hemisphere.
template <typename Brdf>
double worstRelativeDifference(const fit::FittedMaterial& m, const Brdf& actual) {
  double worst = 0.0;
  for (double thetaI : {0.0, 20.0, 45.0, 70.0})
    for (double phiI : {0.0, 60.0, 130.0, 250.0})
      for (double thetaV : {10.0, 35.0, 60.0, 80.0})
        for (double phiV : {15.0, 100.0, 200.0, 300.0}) {
          const V3 l = direction(thetaI, phiI), v = direction(thetaV, phiV);
          const Rgb expected = m.evaluate({l.x, l.y, l.z}, {v.x, v.y, v.z});
          const Rgb value = actual(l, v);
          for (std::size_t c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(value[c] - expected[c]) / std::max(expected[c], 1e-3));
        }
  return worst;
}

TEST(GltfMaterial, SpecularLobeEqualsTheFitWhereTheExtensionsReach) {
  const fit::FittedMaterial m = brushedMetal();
  const GltfConversion g = toGltfMaterial(m);
  EXPECT_TRUE(g.losses.empty()) << toString(g.losses.front().kind) << ": " << g.losses.front().detail;
  EXPECT_LT(worstRelativeDifference(m, [&](V3 l, V3 v) { return gltfSpecular(g.material, l, v); }),
            1e-9);
}

TEST(GltfMaterial, RotationIsTheTangentAngleOfTheLargerAlpha) {
  fit::FittedMaterial m = brushedMetal();
  // The same lobe said the other way round: the smaller alpha along a tangent at 120 deg.
  std::swap(m.alphaTangent, m.alphaBitangent);
  m.tangentDeg = 120.0;
  const GltfMaterial g = toGltfMaterial(m).material;
  EXPECT_NEAR(g.anisotropyRotationRad, 30.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_NEAR(g.roughnessFactor * g.roughnessFactor, 0.08, 1e-12);
}

TEST(GltfMaterial, AlphaAboveOneIsClampedAndReported) {
  fit::FittedMaterial m = brushedMetal();
  m.alphaTangent = 1.6;
  const GltfConversion g = toGltfMaterial(m);
  EXPECT_DOUBLE_EQ(g.material.anisotropyStrength, 1.0);
  ASSERT_FALSE(g.losses.empty());
  EXPECT_EQ(g.losses.front().kind, LossKind::RoughnessClamped);
  EXPECT_NE(g.losses.front().detail.find("1.6"), std::string::npos) << g.losses.front().detail;
}

TEST(GltfMaterial, F0AboveF90IsReported) {
  fit::FittedMaterial m = brushedMetal();
  m.specularF90 = 0.3;  // red f0 0.55 > 0.3: a Fresnel that falls toward grazing
  const GltfConversion g = toGltfMaterial(m);
  const auto found = std::find_if(g.losses.begin(), g.losses.end(), [](const ConversionLoss& l) {
    return l.kind == LossKind::SpecularColourAtGrazing;
  });
  EXPECT_NE(found, g.losses.end());
  // F0 is kept (the face-on highlight); F90 is raised to the brightest f0: a flat Fresnel.
  EXPECT_DOUBLE_EQ(g.material.specularFactor, 0.55);
  const double iorF0 = std::pow((g.material.ior - 1.0) / (g.material.ior + 1.0), 2);
  for (std::size_t c = 0; c < 3; ++c)
    EXPECT_NEAR(iorF0 * g.material.specularColorFactor[c] * g.material.specularFactor, m.specularF0[c], 1e-12);
}

TEST(GltfMaterial, DiffuseIsRaisedToMatchAtNormalIncidenceAndReported) {
  fit::FittedMaterial m = brushedMetal();
  m.specularF0 = Rgb::gray(0.04);
  m.specularF90 = 1.0;
  m.diffuseAlbedo = Rgb{0.5, 0.2, 0.1};
  const GltfConversion g = toGltfMaterial(m);
  EXPECT_NEAR(g.material.baseColorFactor[0], 0.5 / 0.96, 1e-12);
  EXPECT_NEAR(g.material.ior, 1.5, 1e-9);  // F0 0.04 is glTF's default dielectric
  EXPECT_TRUE(std::any_of(g.losses.begin(), g.losses.end(), [](const ConversionLoss& l) {
    return l.kind == LossKind::DiffuseLayering;
  }));
}

TEST(GltfMaterial, SheenRoughnessIsTheSquareRootOfTheCharlieExponentsR) {
  fit::FittedMaterial m = brushedMetal();
  m.model = fit::MaterialModel::GgxSheen;
  m.sheenColour = Rgb{0.3, 0.1, 0.1};
  m.sheenRoughness = 0.36;
  m.diffuseAlbedo = Rgb{0.3, 0.2, 0.1};
  const auto sheenLoss = [](const ConversionLoss& l) { return l.kind == LossKind::SheenForm; };
  // The khr form is the extension's own: its factors as fitted, the base colour not raised.
  m.sheenForm = fit::SheenForm::Khr;
  const GltfConversion khr = toGltfMaterial(m);
  EXPECT_TRUE(khr.material.hasSheen);
  EXPECT_NEAR(khr.material.sheenRoughnessFactor, 0.6, 1e-12);
  EXPECT_DOUBLE_EQ(khr.material.sheenColorFactor[0], 0.3);
  EXPECT_FALSE(std::any_of(khr.losses.begin(), khr.losses.end(), sheenLoss));
  // The additive form (version 1) is not: a loss, and the base raised under the sheen.
  m.sheenForm = fit::SheenForm::Additive;
  const GltfConversion additive = toGltfMaterial(m);
  EXPECT_NEAR(additive.material.sheenRoughnessFactor, 0.6, 1e-12);
  EXPECT_TRUE(std::any_of(additive.losses.begin(), additive.losses.end(), sheenLoss));
  EXPECT_GT(additive.material.baseColorFactor[0], khr.material.baseColorFactor[0]);
}

TEST(GltfMaterial, NoSpecularAtAllIsSpecularFactorZero) {
  fit::FittedMaterial m = brushedMetal();
  m.specularF0 = Rgb{};
  m.specularF90 = 0.0;
  m.diffuseAlbedo = Rgb{0.4, 0.4, 0.4};
  const GltfConversion g = toGltfMaterial(m);
  EXPECT_DOUBLE_EQ(g.material.specularFactor, 0.0);
  EXPECT_DOUBLE_EQ(g.material.baseColorFactor[0], 0.4);
  EXPECT_TRUE(g.losses.empty());
}

TEST(GltfBrdf, TheFitsCoatIsTheClearcoatExtensionExactly) {
  fit::FittedMaterial m = brushedMetal();
  m.model = fit::MaterialModel::GgxCoat;
  m.coatWeight = 0.75;
  m.coatAlpha = 0.05;
  const GltfConversion g = toGltfMaterial(m);
  EXPECT_TRUE(g.losses.empty());
  EXPECT_TRUE(g.material.hasClearcoat);
  const GltfBrdf brdf(gltfMaterialJson(g.material));
  EXPECT_LT(worstRelativeDifference(
                m, [&](V3 l, V3 v) { return brdf.evaluate({l.x, l.y, l.z}, {v.x, v.y, v.z}); }),
            1e-9);
  // The coat is there to be lost: without it, the glTF BRDF is visibly off the coated fit (the
  // bright metal under it hides a 4 % coat face on; dE 0.52).
  GltfMaterial uncoated = g.material;
  uncoated.hasClearcoat = false;
  EXPECT_GT(eval::compare(fit::tabulate(m), tabulate(GltfBrdf(gltfMaterialJson(uncoated)))).deltaE, 0.3);
}

TEST(GltfMaterial, ACoatRougherThanTheExtensionReachesIsClampedAndReported) {
  fit::FittedMaterial m = brushedMetal();
  m.model = fit::MaterialModel::GgxCoat;
  m.coatWeight = 0.5;
  m.coatAlpha = 1.6;
  const GltfConversion g = toGltfMaterial(m);
  EXPECT_DOUBLE_EQ(g.material.clearcoatRoughnessFactor, 1.0);
  ASSERT_EQ(g.losses.size(), 1u);
  EXPECT_EQ(g.losses.front().kind, LossKind::RoughnessClamped);
  EXPECT_NE(g.losses.front().detail.find("coat alpha 1.6"), std::string::npos);
}

TEST(GltfBrdf, MetalMatchesTheFitAndTheSheenLossIsMeasured) {
  // Specular-dominated: only the (raised) diffuse's Fresnel fading differs.
  EXPECT_LT(gltfVersusFit(brushedMetal()).deltaE, 0.05);
  fit::FittedMaterial velvet;
  velvet.model = fit::MaterialModel::GgxSheen;
  velvet.diffuseAlbedo = Rgb{0.15, 0.01, 0.02};
  velvet.specularF0 = Rgb{};
  velvet.specularF90 = 0.0;
  velvet.sheenColour = Rgb{0.7, 0.15, 0.15};
  velvet.sheenRoughness = 0.3;
  // The khr form is the extension's layering: only the albedo E's two quadratures differ
  // (the fit's table, the check's own integral) and the diffuse's Fresnel fading (none here).
  velvet.sheenForm = fit::SheenForm::Khr;
  EXPECT_LT(gltfVersusFit(velvet).deltaE, 0.05);
  // The additive form (format version 1): glTF dims the base by the sheen's albedo and its
  // visibility is Charlie's, a real loss that the base colour's raise does not remove
  // (velvet-red by the specification: 2.52, issue 46).
  velvet.sheenForm = fit::SheenForm::Additive;
  EXPECT_GT(gltfVersusFit(velvet).deltaE, 0.5);
  const GltfBrdf brdf(gltfMaterialJson(toGltfMaterial(velvet).material));
  for (double mu : {0.05, 0.5, 1.0}) {
    EXPECT_GT(brdf.sheenAlbedo(mu), 0.0);
    EXPECT_LT(brdf.sheenAlbedo(mu), 1.0);
  }
}

}  // namespace
}  // namespace slicecap::material_export
