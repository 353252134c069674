// The BRDF a glTF renderer draws from the exported factors, evaluated as the specifications write
// it, so that the glTF export's loss is a measured dE against the fitted material, not only words.
#pragma once

#include <array>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/material_export/gltf_material.hpp"

namespace slicecap::material_export {

/// \brief glTF's BRDF of `GltfMaterial` in the frame tangent = x, bitangent = y, normal = z:
///   f = f_sheen + s (diffuse (1 - F) + F D V),  s = min(1 - max(sheen) E(n.v), 1 - max(sheen) E(n.l))
/// - D, V: KHR_materials_anisotropy's D_GGX_anisotropic and V_GGX_anisotropic (without the sample
///   code's clamp of V to 1, a renderer's guard);
/// - F: Schlick with F0 = F0(ior) specularFactor specularColorFactor, F90 = specularFactor
///   (KHR_materials_specular + KHR_materials_ior), mixing the diffuse per channel as glTF 2.0
///   Appendix B's fresnel_mix does;
/// - sheen: KHR_materials_sheen's Charlie D (alpha = sheenRoughnessFactor^2) with the visibility
///   1 / (4 (n.l + n.v - n.l n.v)), and its albedo scaling s with E, the sheen's directional albedo,
///   integrated numerically (32 x 64 midpoint rule, tabulated at 33 cosines);
/// - clear coat: KHR_materials_clearcoat's fresnel_coat, f -> f (1 - c Fc) + c Fc D V of an
///   isotropic GGX of alpha clearcoatRoughnessFactor^2, Fc = 0.04 + 0.96 (1 - n.v)^5, c =
///   clearcoatFactor.
class GltfBrdf {
 public:
  explicit GltfBrdf(const GltfMaterial& material);
  /// \brief f_r in 1/sr for unit vectors toward the light and the viewer (z > 0).
  Rgb evaluate(const UnitVector& toLight, const UnitVector& toView) const;
  /// \brief E(cos theta): the sheen lobe's directional albedo (without its colour); 0 without sheen.
  double sheenAlbedo(double cosTheta) const;

 private:
  double sheenLobe(const UnitVector& l, const UnitVector& v) const;  // D V, without the colour

  GltfMaterial material_;
  static constexpr int kAlbedoSamples = 33;
  std::array<double, kAlbedoSamples> sheenAlbedo_{};  // E at cos theta = i / 32
};

/// \brief The glTF BRDF on the Bonn grid (as fit::tabulate).
Abrdf tabulate(const GltfBrdf& brdf);

/// \brief How far what a glTF renderer draws is from the fit: the metrics of `slicecap compare`
/// with the fitted material's table as the reference. Throws std::invalid_argument when the fitted
/// material reflects nothing (eval::compare's reference).
eval::Metrics gltfVersusFit(const fit::FittedMaterial& fitted);

}  // namespace slicecap::material_export
