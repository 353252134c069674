// Which glTF form the one-material export writes: the dielectric + KHR_materials_specular form of
// toGltfMaterial, or, for a coloured specular over a diffuse, a metal blend that renderers which
// dim the diffuse per channel draw as the specification does (docs/material-export.md).
#pragma once

#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/material_export/gltf_material.hpp"

namespace slicecap::material_export {

/// \brief The most a chosen form may be from the fit by the specification (GltfBrdf against the
/// fit's table, mean dE): issue 46's goal for every glTF export.
inline constexpr double kGltfSpecGoalDeltaE = 0.3;

/// \brief The fit as the metal blend: metallicFactor m = sum(f0) / (sum(f0) + sum(diffuse)),
/// baseColorFactor f0 / m (at most 1), specularFactor 0 (no dielectric specular, so no diffuse
/// dimming in any reading), lobe, sheen and coat as toGltfMaterial maps them. By glTF 2.0
/// Appendix B its Fresnel is m (f0/m + (1 - f0/m) (1 - v.h)^5) -> f0 face on, m at grazing, and
/// its diffuse (1 - m) f0 / m, the fit's where the diffuse is in proportion to f0. Never throws.
GltfMaterial metalBlend(const fit::FittedMaterial& fitted);

/// \brief toGltfMaterial's factors, or the metal blend where KHR_materials_specular's
/// `1 - max_value(F)` and a renderer's per-channel `1 - F` (three.js 0.187) disagree: a fit with a
/// coloured f0 over a diffuse. The rule, by GltfBrdf against the fit's table (mean dE): the metal
/// blend when it is within kGltfSpecGoalDeltaE by the specification and nearer the fit than the
/// dielectric form is in the worse of the two readings; otherwise the dielectric form, with the
/// per-channel reading's figure among its losses. Only the one-material glTF uses it (the SVBRDF
/// textures and MaterialX keep toGltfMaterial's form). Never throws.
GltfConversion chooseGltfForm(const fit::FittedMaterial& fitted);

}  // namespace slicecap::material_export
