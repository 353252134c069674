// The BRDF a glTF renderer draws from a glTF material as written in the file, evaluated by the
// specifications' formulas, so that the glTF export's loss is a measured dE against the fitted
// material. It reads the material's JSON, not the exporter's factors, and shares no code with the
// exporter's mapping: what the exporter assumes about glTF cannot hide here.
#pragma once

#include <array>
#include <nlohmann/json.hpp>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/error.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::material_export {

/// \brief A glTF material object GltfBrdf cannot read (a factor of the wrong type or length);
/// the message names the field.
class GltfMaterialError : public slicecap::Error {
 public:
  using Error::Error;
};

/// \brief The sheen visibility term: KHR_materials_sheen's "Charlie" one (its sample
/// implementation) or the simpler Ashikhmin one the extension allows,
/// 1 / (4 (n.l + n.v - n.l n.v)). The directional albedo E is integrated with the same term.
enum class SheenVisibility { Charlie, Ashikhmin };

/// \brief How the diffuse is dimmed under the dielectric specular: KHR_materials_specular's
/// `1 - max_value(dielectric_fresnel)` in every channel, or each channel by its own `1 - F`, as
/// three.js 0.187 draws it (RE_Direct_Physical in lights_physical_pars_fragment.glsl.js), which
/// the specification does not allow: a reading to measure what such a renderer shows.
enum class DiffuseDimming { MaxValue, PerChannel };

/// \brief glTF's BRDF of one material object in the frame TANGENT = x, bitangent = y, normal = z,
/// factors read from the JSON with the specifications' defaults where absent:
/// - glTF 2.0 Appendix B: material = mix(dielectric_brdf, metal_brdf, metallic), metal_brdf =
///   specular_brdf (baseColor + (1 - baseColor) (1 - v.h)^5), diffuse_brdf = baseColor / pi;
/// - KHR_materials_specular + _ior: dielectric_fresnel = mix(min(F0(ior) specularColor, 1)
///   specular, specular, (1 - v.h)^5), dielectric_brdf = dielectric_fresnel specular_brdf +
///   (1 - max_value(dielectric_fresnel)) diffuse_brdf;
/// - KHR_materials_anisotropy: specular_brdf = V D of its D_GGX_anisotropic and
///   V_GGX_anisotropic, alpha_t = mix(roughness^2, 1, strength^2) along TANGENT turned by
///   anisotropyRotation toward the bitangent, alpha_b = roughness^2 (without the sample code's
///   clamp of V to 1, a renderer's guard);
/// - KHR_materials_sheen: sheenColor D_charlie V_sheen + material min(1 - max3(sheenColor) E(n.v),
///   1 - max3(sheenColor) E(n.l)), alpha_g = sheenRoughness^2, E the sheen's directional albedo
///   integrated numerically (32 x 64 midpoint rule at 65 cosines);
/// - KHR_materials_clearcoat: mix(sheen_material, V D of isotropic GGX(clearcoatRoughness^2),
///   clearcoat (0.04 + 0.96 (1 - n.v)^5)).
class GltfBrdf {
 public:
  /// \brief Throws GltfMaterialError naming the field when a factor has the wrong type or length.
  explicit GltfBrdf(const nlohmann::ordered_json& material,
                    SheenVisibility visibility = SheenVisibility::Charlie,
                    DiffuseDimming dimming = DiffuseDimming::MaxValue);
  /// \brief f_r in 1/sr for unit vectors toward the light and the viewer (z > 0).
  Rgb evaluate(const UnitVector& toLight, const UnitVector& toView) const;
  /// \brief E(cos theta): the sheen's directional albedo (without its colour); 0 without sheen.
  double sheenAlbedo(double cosTheta) const;

 private:
  double sheenLobe(const UnitVector& l, const UnitVector& v) const;  // D V, without the colour

  struct Factors {
    Rgb baseColor = Rgb::gray(1.0);
    double metallic = 1.0, roughness = 1.0;
    double anisotropyStrength = 0.0, anisotropyRotationRad = 0.0;
    double specular = 1.0;
    Rgb specularColor = Rgb::gray(1.0);
    double ior = 1.5;
    Rgb sheenColor;
    double sheenRoughness = 0.0;
    double clearcoat = 0.0, clearcoatRoughness = 0.0;
  };
  Factors f_;
  SheenVisibility visibility_;
  DiffuseDimming dimming_;
  static constexpr int kAlbedoSamples = 65;
  std::array<double, kAlbedoSamples> sheenAlbedo_{};  // E at cos theta = i / 64
};

/// \brief The glTF BRDF on the Bonn grid (as fit::tabulate).
Abrdf tabulate(const GltfBrdf& brdf);

/// \brief How far what a glTF renderer draws is from the fit: the glTF material the export writes
/// (gltfMaterialJson), evaluated by GltfBrdf, against the fitted material's table, with the
/// metrics of `slicecap compare`. Throws eval::EvalError when the fitted material reflects
/// nothing (eval::compare's reference): gltfVersusFitExists says so first.
eval::Metrics gltfVersusFit(const fit::FittedMaterial& fitted,
                            SheenVisibility visibility = SheenVisibility::Charlie);

/// \brief Whether gltfVersusFit has figures for `fitted`: false for a material that reflects
/// nothing (no table to compare against).
bool gltfVersusFitExists(const fit::FittedMaterial& fitted);

}  // namespace slicecap::material_export
