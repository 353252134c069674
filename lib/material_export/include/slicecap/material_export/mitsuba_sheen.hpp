// The fitted Charlie sheen as Mitsuba 3's principled BSDF can hold it: the least-squares nearest
// diffuse-with-retro-reflection and Disney sheen terms (docs/material-export.md, Mitsuba section).
#pragma once

#include "slicecap/core/grid.hpp"

namespace slicecap::material_export {

/// \brief Mitsuba's principled BSDF terms that stand in for the fitted sheen lobe, as multiples of
/// the sheen colour: sheenColour x (diffuseScale x P_roughness(l, v) + sheenScale x Fd(l, v)).
struct SheenApproximation {
  double diffuseScale = 0.0;    ///< weight of principledDiffuseLobe (a base colour of sheenColour x this)
  double roughness = 0.0;       ///< principled `roughness` of that lobe, [0, 1]
  double sheenScale = 0.0;      ///< weight of principledSheenLobe
  double relativeMismatch = 1.0;  ///< rms(approximation - Charlie) / rms(Charlie), radiance-weighted
};

/// \brief Mitsuba 3 principled's diffuse and retro-reflection per unit base colour, 1/sr:
/// ((1 - Fl/2)(1 - Fv/2) + Rr (Fl + Fv + Fl Fv (Rr - 1))) / pi, F = (1 - cos)^5, Rr = 2 roughness
/// cos_d^2 (its `eval`, no flatness, metallic 0).
double principledDiffuseLobe(const UnitVector& toLight, const UnitVector& toView, double roughness);

/// \brief Mitsuba 3 principled's sheen per unit `sheen` (untinted), 1/sr: (1 - cos_d)^5, cos_d the
/// angle between the half vector and either direction.
double principledSheenLobe(const UnitVector& toLight, const UnitVector& toView);

/// \brief The non-negative least-squares fit of those two terms to the fitted Charlie lobe of this
/// roughness (fit::FittedMaterial's, colour 1) over every pair of the 81 Bonn directions, each
/// residual weighted by cos(light) (the rendered radiance), the principled roughness the best of
/// 0, 0.05, ..., 1. Never fails; relativeMismatch 1 would be no better than leaving the sheen out.
SheenApproximation approximateSheen(double charlieRoughness);

}  // namespace slicecap::material_export
