// The fitted material as glTF 2.0 material factors: core metallic-roughness plus
// KHR_materials_anisotropy, KHR_materials_specular, KHR_materials_ior, KHR_materials_sheen and
// KHR_materials_clearcoat.
#pragma once

#include <vector>

#include "slicecap/core/rgb.hpp"
#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/material_export/conversion_loss.hpp"

namespace slicecap::material_export {

/// \brief glTF material factors (no textures), in the spelling of the glTF JSON.
struct GltfMaterial {
  Rgb baseColorFactor;               ///< pbrMetallicRoughness.baseColorFactor (alpha 1)
  double metallicFactor = 0.0;       ///< pbrMetallicRoughness.metallicFactor (0 but in chooseGltfForm's metal blend)
  double roughnessFactor = 1.0;      ///< pbrMetallicRoughness.roughnessFactor
  double anisotropyStrength = 0.0;   ///< KHR_materials_anisotropy
  double anisotropyRotationRad = 0;  ///< KHR_materials_anisotropy, counter-clockwise from TANGENT
  double specularFactor = 1.0;       ///< KHR_materials_specular (the dielectric F90)
  Rgb specularColorFactor = Rgb::gray(1.0);  ///< KHR_materials_specular
  double ior = 1.5;                  ///< KHR_materials_ior
  bool hasSheen = false;             ///< write KHR_materials_sheen
  Rgb sheenColorFactor;              ///< KHR_materials_sheen
  double sheenRoughnessFactor = 0.0; ///< KHR_materials_sheen
  bool hasClearcoat = false;         ///< write KHR_materials_clearcoat
  double clearcoatFactor = 0.0;      ///< KHR_materials_clearcoat
  double clearcoatRoughnessFactor = 0.0;  ///< KHR_materials_clearcoat (alpha = its square)
};

/// \brief The factors and what they cannot express.
struct GltfConversion {
  GltfMaterial material;
  std::vector<ConversionLoss> losses;
};

/// \brief Maps a fitted material onto glTF. Never throws. The mapping (docs/material-export.md):
/// - GGX lobe: KHR_materials_anisotropy stretches one axis, alpha_t = mix(alpha, 1, strength^2),
///   alpha_b = alpha = roughnessFactor^2 (KHR_materials_anisotropy README, "Anisotropy"). The
///   canonical fit's tangent is the larger alpha, so roughnessFactor = sqrt(alpha_bitangent),
///   strength = sqrt((alpha_tangent - alpha_bitangent) / (1 - alpha_bitangent)): exact while
///   alpha_tangent <= 1; larger alphas are clamped to 1 (RoughnessClamped).
/// - Rotation: radians(tangent_deg), on a mesh whose TANGENT is the table's x axis and whose
///   bitangent (cross(normal, tangent) * w, w = +1) is its y axis.
/// - Fresnel: KHR_materials_specular + KHR_materials_ior give F0 = F0(ior) * specularFactor *
///   specularColorFactor and F90 = specularFactor (KHR_materials_specular README,
///   "Implementation"), exactly the fit's Schlick f0/f90 when f0 <= f90 per channel; otherwise F0
///   is kept and F90 raised to max f0 (SpecularColourAtGrazing): glTF's F0 cannot exceed its F90.
/// - The diffuse: glTF dims it by the specular's reflectance; baseColorFactor is raised by
///   1 / (1 - max f0) (the extension dims it by 1 - max_value(F) in every channel) so that it
///   matches at normal incidence (DiffuseLayering).
/// - Sheen: sheenRoughnessFactor = sqrt(sheen_roughness) (glTF's Charlie alpha is its square).
/// - Coat: the fit's coat is KHR_materials_clearcoat's layering (IOR 1.5), so clearcoatFactor =
///   coat_weight and clearcoatRoughnessFactor = sqrt(coat_alpha), exact while coat_alpha <= 1
///   (larger: RoughnessClamped).
GltfConversion toGltfMaterial(const fit::FittedMaterial& fitted);

}  // namespace slicecap::material_export
