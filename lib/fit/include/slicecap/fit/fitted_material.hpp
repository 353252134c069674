// The parametric material `slicecap fit` produces: Lambertian diffuse + anisotropic GGX + optional
// sheen + optional clear coat, with the conventions the JSON and the exports rely on.
#pragma once

#include <string_view>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap::fit {

/// \brief Which terms a fitted material has.
enum class MaterialModel { Ggx, GgxSheen, GgxCoat, GgxSheenCoat };

/// \brief "ggx", "ggx+sheen", "ggx+coat" or "ggx+sheen+coat" (the spelling of the JSON's "model").
std::string_view toString(MaterialModel model);
bool hasSheen(MaterialModel model);
bool hasCoat(MaterialModel model);
/// \brief The model with the given terms.
MaterialModel modelWith(bool sheen, bool coat);

/// \brief How a sheen joins the base (the JSON's "sheen_form").
///
/// Khr (what every fit makes since format version 2): glTF KHR_materials_sheen's layering, so that
/// a viewer following the extension renders the fit: sheen_colour D_charlie V_charlie + base
/// min(1 - s E(cos_v), 1 - s E(cos_l)), s the largest sheen channel, V_charlie the extension's
/// "Charlie" visibility and E its directional albedo (sheen_albedo.hpp).
/// Additive (format version 1): the sheen D_charlie / (4 (cos_i + cos_v - cos_i cos_v))
/// (Ashikhmin's visibility) added on top of a base that is not dimmed; models::makeSheen's form.
/// Files of version 1 hold it, and are still evaluated in it.
enum class SheenForm { Khr, Additive };

/// \brief "khr_materials_sheen" or "additive" (the JSON's spelling).
std::string_view toString(SheenForm form);

/// \brief The clear coat's Schlick reflectance at normal incidence: a dielectric of IOR 1.5, glTF
/// KHR_materials_clearcoat's fixed coat IOR ((1.5 - 1) / (1.5 + 1))^2.
inline constexpr double kCoatF0 = 0.04;

/// \brief f_r(l, v) = diffuse / pi + F(l.h) D(h) G2(l, v) / (4 cos_i cos_v) + sheen term, 1/sr.
///
/// D: anisotropic GGX with alpha = roughness^2 convention (alphaTangent along the tangent,
/// alphaBitangent across it); G2: height-correlated Smith; F: Schlick with per-channel f0 and a
/// grey f90, F = f0 + (f90 - f0) (1 - l.h)^5. With f90 = 1 this is the lobe of
/// models::makeAnisotropicGgx, so a GGX table is matched exactly; f90 < 1 (glTF's
/// KHR_materials_specular "specular" factor) lets the lobe fade at grazing angles too, and f0 = f90
/// = 0 removes it: without it no fit could describe a material with no specular (a velvet, a
/// matte paint), whose Schlick edge would otherwise always reflect.
/// Sheen: the "Charlie" distribution (Estevez and Kulla 2017), joined to the terms above as
/// `sheenForm` says (SheenForm); zero when the model has none.
///
/// Clear coat (models ending in "+coat"): glTF KHR_materials_clearcoat's layering with its fixed
/// IOR 1.5, so that the glTF export is the fitted material and not an approximation of it:
/// f_r = base (1 - w Fc) + w Fc D_ggx(alpha_c) G2(alpha_c) / (4 cos_i cos_v), with base the terms
/// above, w = coatWeight, Fc = 0.04 + 0.96 (1 - cos_v)^5 (the view's cosine with the normal, as
/// the extension's fresnel_coat, not l.h) and an isotropic GGX lobe of alpha coatAlpha.
///
/// Conventions (canonical(), what every fit returns): the tangent lies at `tangentDeg`
/// counter-clockwise from the table's azimuth-0 axis (x of the Bonn grid, docs/method.md §1.2), in
/// [0, 180) because the lobe is symmetric under a half turn, and it is the axis of the LARGER
/// roughness: alphaTangent >= alphaBitangent (glTF KHR_materials_anisotropy's anisotropy
/// direction; a highlight is stretched along it in half-vector space).
struct FittedMaterial {
  MaterialModel model = MaterialModel::Ggx;
  Rgb diffuseAlbedo;           ///< Lambertian albedo; the diffuse BRDF is this / pi
  Rgb specularF0;              ///< Schlick reflectance at normal incidence, [0, 1]
  double specularF90 = 1.0;    ///< Schlick reflectance at grazing incidence, [0, 1]
  double alphaTangent = 0.1;   ///< GGX alpha along the tangent
  double alphaBitangent = 0.1; ///< GGX alpha across the tangent
  double tangentDeg = 0.0;     ///< tangent azimuth, deg, counter-clockwise from x
  Rgb sheenColour;             ///< sheen tint (zero for Ggx)
  double sheenRoughness = 0.5; ///< Charlie roughness r (exponent 1 / r); unused for Ggx
  SheenForm sheenForm = SheenForm::Khr;  ///< how the sheen joins the base; unused for Ggx
  double coatWeight = 0.0;     ///< clear coat weight w, [0, 1] (glTF clearcoatFactor)
  double coatAlpha = 0.1;      ///< GGX alpha of the isotropic coat lobe (clearcoatRoughness^2)

  /// \brief f_r for unit vectors toward the light and the viewer (z > 0), 1/sr.
  Rgb evaluate(const UnitVector& toLight, const UnitVector& toView) const;
  /// \brief The same material in the canonical convention above (swaps the alphas and turns the
  /// tangent by 90 deg when alphaTangent < alphaBitangent; wraps the tangent into [0, 180)).
  FittedMaterial canonical() const;
};

/// \brief The material's 81 x 81 table on the Bonn grid (as models::tabulate).
Abrdf tabulate(const FittedMaterial& material);

/// \brief The tangent difference a - b of two lobe orientations, in (-90, 90] deg (the lobe repeats
/// every 180 deg).
double tangentDifferenceDeg(double aDeg, double bDeg);

}  // namespace slicecap::fit
