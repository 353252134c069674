// The glTF check: the BRDF of a glTF material object as the specifications write it, read from the
// JSON the export writes, and the export measured by it where the exporter and the specification
// could disagree (issue 46).
#include "slicecap/material_export/gltf_brdf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slicecap/fit/material_fit.hpp"
#include "slicecap/material_export/gltf_material.hpp"
#include "slicecap/material_export/gltf_writer.hpp"

namespace slicecap::material_export {
namespace {

using json = nlohmann::ordered_json;

constexpr UnitVector kNormal{0.0, 0.0, 1.0};

// A dielectric whose specular reflects red only: F0 = F0(1.5) x 10 = 0.4 in red, 0 elsewhere.
json redSpecularWhiteBase() {
  return {{"pbrMetallicRoughness",
           {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}}},
          {"extensions",
           {{"KHR_materials_specular", {{"specularFactor", 1.0}, {"specularColorFactor", {10.0, 0.0, 0.0}}}},
            {"KHR_materials_ior", {{"ior", 1.5}}}}}};
}

// KHR_materials_specular: "(1 - max_value(dielectric_fresnel)) diffuse_brdf": the red Fresnel
// dims the green and blue diffuse too, not each channel by its own F.
TEST(GltfBrdf, DimsTheDiffuseOfEveryChannelByTheLargestFresnel) {
  const GltfBrdf brdf(redSpecularWhiteBase());
  const Rgb face = brdf.evaluate(kNormal, kNormal);  // v.h = 1: F = F0
  EXPECT_NEAR(face[1], (1.0 - 0.4) / std::numbers::pi, 1e-12);
  EXPECT_NEAR(face[2], (1.0 - 0.4) / std::numbers::pi, 1e-12);
  EXPECT_GT(face[0], face[1]);  // red also has its specular lobe
}

TEST(GltfBrdf, ReadsTheSpecificationsDefaultsAndNamesAFactorOfTheWrongType) {
  // An empty material is glTF's default: a white rough metal (metallicFactor 1, roughness 1).
  const Rgb metal = GltfBrdf(json::object()).evaluate(kNormal, kNormal);
  EXPECT_GT(metal[0], 0.0);
  EXPECT_DOUBLE_EQ(metal[0], metal[2]);
  json bad = redSpecularWhiteBase();
  bad["extensions"]["KHR_materials_specular"]["specularColorFactor"] = {1.0, 1.0};
  try {
    GltfBrdf brdf(bad);
    FAIL() << "a two-number specularColorFactor was read";
  } catch (const GltfMaterialError& e) {
    EXPECT_NE(std::string(e.what()).find("specularColorFactor"), std::string::npos) << e.what();
  }
}

// The export measured by the specification where the exporter's old reading (each channel dimmed
// by its own 1 - F) disagrees with it: a coloured specular over a diffuse, at normal incidence,
// must be the fit in every channel.
TEST(GltfBrdf, ColouredSpecularOverADiffuseIsTheFitFaceOnInEveryChannel) {
  fit::FittedMaterial steel;
  steel.diffuseAlbedo = Rgb{0.10, 0.20, 0.30};
  steel.specularF0 = Rgb{0.50, 0.30, 0.10};
  steel.specularF90 = 1.0;
  steel.alphaTangent = 0.3;
  steel.alphaBitangent = 0.1;
  steel.tangentDeg = 30.0;
  const GltfBrdf brdf(gltfMaterialJson(toGltfMaterial(steel).material));
  const Rgb gltf = brdf.evaluate(kNormal, kNormal), fitted = steel.evaluate(kNormal, kNormal);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(gltf[c] / fitted[c], 1.0, 1e-9) << c;
}

}  // namespace
}  // namespace slicecap::material_export

namespace slicecap::material_export {
namespace {

// A velvet made by KHR_materials_sheen's own formula (the check evaluates it from the extension's
// text): its table fitted, and the fit's glTF export evaluated by the specification again. Issue
// 46's goal: the export within 0.3 dE of its fit (before the fit's khr sheen form: the fit 0.99,
// its export 3.87 from the truth).
TEST(GltfBrdf, AVelvetMadeByTheExtensionsFormulaFitsAndExportsWithinAThirdOfADeltaE) {
  const json velvet = {
      {"pbrMetallicRoughness",
       {{"baseColorFactor", {0.12, 0.02, 0.03, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
      {"extensions",
       {{"KHR_materials_specular", {{"specularFactor", 0.0}}},
        {"KHR_materials_sheen", {{"sheenColorFactor", {0.8, 0.2, 0.25}}, {"sheenRoughnessFactor", 0.6}}}}}};
  const Abrdf truth = tabulate(GltfBrdf(velvet));
  const fit::FitResult fitted = fit::fitMaterial(truth, "spec-velvet");
  ASSERT_TRUE(fit::hasSheen(fitted.material.model)) << fitted.choiceReason;
  EXPECT_EQ(fitted.material.sheenForm, fit::SheenForm::Khr);
  EXPECT_LT(fitted.metrics.deltaE, 0.1);
  EXPECT_NEAR(fitted.material.sheenRoughness, 0.36, 0.02);
  EXPECT_LT(gltfVersusFit(fitted.material).deltaE, 0.3);
  const GltfBrdf exported(gltfMaterialJson(toGltfMaterial(fitted.material).material));
  EXPECT_LT(eval::compare(truth, tabulate(exported)).deltaE, 0.3);
}

}  // namespace
}  // namespace slicecap::material_export
