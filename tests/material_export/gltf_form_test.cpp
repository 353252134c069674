// Which glTF form the one-material export writes: a coloured specular over a diffuse goes out as
// the metal blend when the specification's BRDF keeps it within the goal (issue 46; three.js 0.187
// dims the diffuse per channel, the specification by the largest channel's Fresnel).
#include "slicecap/material_export/gltf_form.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <string>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/material_export/gltf_brdf.hpp"
#include "slicecap/material_export/gltf_writer.hpp"

namespace slicecap::material_export {
namespace {

// copper-ggx-15 as `slicecap fit` finds it: a coloured f0 over a small diffuse.
fit::FittedMaterial copper() {
  fit::FittedMaterial m;
  m.diffuseAlbedo = Rgb{0.02, 0.01, 0.01};
  m.specularF0 = Rgb{0.95, 0.64, 0.54};
  m.specularF90 = 1.0;
  m.alphaTangent = 0.3;
  m.alphaBitangent = 0.12;
  m.tangentDeg = 15.0;
  return m;
}

// satin-red-90's fit: a coloured f0 falling to f90 = 0 over a strong red diffuse.
fit::FittedMaterial redSatin() {
  fit::FittedMaterial m;
  m.diffuseAlbedo = Rgb{0.34, 0.043, 0.053};
  m.specularF0 = Rgb{0.111, 0.086, 0.087};
  m.specularF90 = 0.0;
  m.alphaTangent = 0.4;
  m.alphaBitangent = 0.1;
  m.tangentDeg = 0.0;
  return m;
}

double deltaE(const fit::FittedMaterial& m, const GltfMaterial& g, DiffuseDimming dimming) {
  return eval::compare(fit::tabulate(m),
                       tabulate(GltfBrdf(gltfMaterialJson(g), SheenVisibility::Charlie, dimming)))
      .deltaE;
}

bool hasLossMentioning(const GltfConversion& c, const std::string& text) {
  return std::any_of(c.losses.begin(), c.losses.end(), [&](const ConversionLoss& loss) {
    return loss.kind == LossKind::DiffuseLayering && loss.detail.find(text) != std::string::npos;
  });
}

// The per-channel reading is what three.js 0.187 draws: the red Fresnel leaves green's diffuse.
TEST(GltfForm, ThePerChannelReadingDimsEachChannelByItsOwnFresnel) {
  const nlohmann::ordered_json material = {
      {"pbrMetallicRoughness",
       {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}}},
      {"extensions",
       {{"KHR_materials_specular", {{"specularFactor", 1.0}, {"specularColorFactor", {10.0, 0.0, 0.0}}}},
        {"KHR_materials_ior", {{"ior", 1.5}}}}}};
  const UnitVector n{0.0, 0.0, 1.0};
  const Rgb perChannel = GltfBrdf(material, SheenVisibility::Charlie, DiffuseDimming::PerChannel)
                             .evaluate(n, n);
  EXPECT_NEAR(perChannel[1], 1.0 / std::numbers::pi, 1e-12);
  EXPECT_LT(GltfBrdf(material).evaluate(n, n)[1], perChannel[1]);
}

TEST(GltfForm, AColouredMetalGoesOutAsTheMetalBlendWithinTheGoalInBothReadings) {
  const fit::FittedMaterial m = copper();
  const GltfConversion chosen = chooseGltfForm(m);
  EXPECT_GT(chosen.material.metallicFactor, 0.9);
  EXPECT_EQ(chosen.material.specularFactor, 0.0);
  const double bySpec = deltaE(m, chosen.material, DiffuseDimming::MaxValue);
  EXPECT_LE(bySpec, kGltfSpecGoalDeltaE);
  EXPECT_DOUBLE_EQ(deltaE(m, chosen.material, DiffuseDimming::PerChannel), bySpec);
  // Why: the dielectric form read per channel is far from the fit.
  EXPECT_GT(deltaE(m, toGltfMaterial(m).material, DiffuseDimming::PerChannel), 1.0);
  EXPECT_TRUE(hasLossMentioning(chosen, "metal blend"));
}

TEST(GltfForm, ADielectricWithAColouredSpecularStaysDielectricAndNamesThePerChannelReading) {
  const fit::FittedMaterial m = redSatin();
  const GltfConversion chosen = chooseGltfForm(m);
  EXPECT_EQ(chosen.material.metallicFactor, 0.0);
  EXPECT_GT(chosen.material.specularFactor, 0.0);
  // The blend would lose the satin (its diffuse is not in proportion to its f0).
  EXPECT_GT(deltaE(m, metalBlend(m), DiffuseDimming::MaxValue), kGltfSpecGoalDeltaE);
  EXPECT_TRUE(hasLossMentioning(chosen, "three.js 0.187"));
}

TEST(GltfForm, AGreySpecularIsLeftAsToGltfMaterialMapsIt) {
  fit::FittedMaterial m = copper();
  m.specularF0 = Rgb::gray(0.9);
  const GltfConversion chosen = chooseGltfForm(m), mapped = toGltfMaterial(m);
  EXPECT_EQ(chosen.material.metallicFactor, 0.0);
  EXPECT_EQ(chosen.losses.size(), mapped.losses.size());
}

TEST(GltfForm, TheFileCarriesTheChosenFormAndItsMeasuredDeltaE) {
  const GltfAsset asset = gltfAsset(copper(), "copper.json");
  const auto& pbr = asset.document["materials"][0]["pbrMetallicRoughness"];
  EXPECT_GT(pbr["metallicFactor"].get<double>(), 0.9);
  ASSERT_TRUE(asset.report.measured.has_value());
  EXPECT_LE(asset.report.measured->deltaE, kGltfSpecGoalDeltaE);
}

TEST(GltfForm, AMaterialThatReflectsNothingIsWrittenWithoutMeasuredFigures) {
  fit::FittedMaterial black = copper();
  black.diffuseAlbedo = Rgb::gray(0.0);
  black.specularF0 = Rgb::gray(0.0);
  black.specularF90 = 0.0;
  EXPECT_FALSE(gltfVersusFitExists(black));
  EXPECT_TRUE(gltfVersusFitExists(copper()));
  const GltfAsset asset = gltfAsset(black, "black.json");
  EXPECT_FALSE(asset.report.measured.has_value());
  EXPECT_TRUE(asset.document.contains("materials"));
}

}  // namespace
}  // namespace slicecap::material_export
