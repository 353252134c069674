// The fitted Charlie sheen as a Mitsuba 3 built-in can hold it: a very rough, fully reflecting
// GGX lobe least-squares fitted to it (docs/material-export.md, Mitsuba section).
#pragma once

#include "slicecap/core/grid.hpp"
#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::material_export {

/// \brief The stand-in for the sheen lobe: sheenColour x scale x ggxStandInLobe(l, v, alpha).
struct SheenApproximation {
  double alpha = 1.0;             ///< isotropic GGX alpha of the stand-in (may exceed 1)
  double scale = 0.0;             ///< its reflectance, as a multiple of the sheen colour
  double relativeMismatch = 1.0;  ///< rms(stand-in - Charlie) / rms(Charlie), radiance-weighted
};

/// \brief Mitsuba 3's `roughconductor` with material "none" (Fresnel 1) per unit
/// specular_reflectance, 1/sr: isotropic GGX D(h) G1(l) G1(v) / (4 cos_l cos_v), G1 the separable
/// Smith term. 0 when either direction is at or below the surface.
double ggxStandInLobe(const UnitVector& toLight, const UnitVector& toView, double alpha);

/// \brief The least-squares stand-in for the fitted Charlie lobe of this roughness
/// (fit::FittedMaterial's in `form`: the khr form's lobe has the extension's Charlie visibility,
/// the additive one Ashikhmin's; colour 1) over every pair of the 81 Bonn directions, each residual
/// weighted by cos(light) (the rendered radiance): for each alpha in 0.05, 0.10, ..., 3 the best
/// scale in [0, maxScale] (maxScale: how much reflectance the snippet has room for), and the alpha
/// with the smallest mismatch. Never fails; with maxScale <= 0 the scale is 0 and the mismatch 1
/// (the sheen left out).
SheenApproximation approximateSheen(double charlieRoughness, double maxScale,
                                    fit::SheenForm form = fit::SheenForm::Khr);

}  // namespace slicecap::material_export
