// The fit -> glTF factor mapping, and a loss for each thing the extensions cannot hold.
#include "slicecap/material_export/gltf_material.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "loss_text.hpp"

namespace slicecap::material_export {
namespace {

// Schlick F0 of a dielectric from its IOR against air, and back.
double iorFromF0(double f0) {
  const double s = std::sqrt(f0);
  return (1.0 + s) / (1.0 - s);
}

// A material this bright at normal incidence is a metal: capping the IOR's F0 at 0.9 keeps the IOR
// finite (37.97) and specularColorFactor at most 1/0.9.
constexpr double kMaxIorF0 = 0.9;
// Below this an F0 or f90 is no specular at all (the fit's bounds reach exactly 0).
constexpr double kNegligible = 1e-6;

std::string format(double v) { return detail::lossFigure(v); }

using Losses = std::vector<ConversionLoss>;

// The lobe: KHR_materials_anisotropy, "Anisotropy": directionAlphaRoughness =
// mix(materialAlphaRoughness, 1.0, strength^2), the perpendicular direction keeps
// materialAlphaRoughness = roughness^2.
void mapLobe(const fit::FittedMaterial& m, GltfMaterial& g, Losses& losses) {
  double alphaT = m.alphaTangent, alphaB = m.alphaBitangent;
  if (alphaB > 1.0) {
    losses.push_back({LossKind::RoughnessClamped,
                      "alpha across the tangent " + format(alphaB) +
                          " > 1: roughnessFactor is capped at 1 (alpha 1)"});
    alphaB = 1.0;
  }
  if (alphaT > 1.0) {
    losses.push_back({LossKind::RoughnessClamped,
                      "alpha along the tangent " + format(alphaT) +
                          " > 1, the most KHR_materials_anisotropy reaches (strength 1): "
                          "exported as alpha 1"});
    alphaT = 1.0;
  }
  g.roughnessFactor = std::sqrt(alphaB);
  g.anisotropyStrength = alphaB < 1.0 ? std::sqrt((alphaT - alphaB) / (1.0 - alphaB)) : 0.0;
  g.anisotropyRotationRad = m.tangentDeg * std::numbers::pi / 180.0;
}

// Fresnel: F0 = F0(ior) * specularFactor * specularColorFactor, F90 = specularFactor, so glTF's
// F0 never exceeds its F90. A fit whose Fresnel falls toward grazing (f0 > f90: the satins fit
// f90 = 0) keeps its F0 exactly and gets F90 = max f0, a flat Fresnel: dropping the lobe, or
// capping F0 at f90, would lose the highlight seen face on.
void mapFresnel(const fit::FittedMaterial& m, GltfMaterial& g, Losses& losses) {
  const double f0Max = m.specularF0.maxChannel();
  Rgb f0Ratio;  // f0 / F90: the part of F0 the colour and the IOR carry
  if (f0Max <= kNegligible && m.specularF90 <= kNegligible) {
    g.specularFactor = 0.0;
  } else {
    g.specularFactor = std::max(m.specularF90, f0Max);
    if (g.specularFactor > m.specularF90 + kNegligible)
      losses.push_back({LossKind::SpecularColourAtGrazing,
                        "f0 " + format(f0Max) + " exceeds f90 " + format(m.specularF90) +
                            ": glTF's Fresnel cannot fall toward grazing, so F90 is raised to " +
                            format(g.specularFactor) + " (a flat Fresnel in the brightest channel)"});
    for (std::size_t c = 0; c < 3; ++c) f0Ratio[c] = m.specularF0[c] / g.specularFactor;
  }
  const double brightest = f0Ratio.maxChannel();
  if (brightest <= kNegligible) {
    g.ior = 1.0;  // F0(1) = 0: no reflection at normal incidence
    g.specularColorFactor = Rgb::gray(1.0);
  } else {
    const double iorF0 = std::min(brightest, kMaxIorF0);
    g.ior = iorFromF0(iorF0);
    for (std::size_t c = 0; c < 3; ++c) g.specularColorFactor[c] = f0Ratio[c] / iorF0;
  }
}

// The diffuse: glTF's dielectric BRDF gives the diffuse the energy the specular leaves, and with
// a coloured specular that is 1 - max_value(F) over the channels, the same in each
// (KHR_materials_specular, "Implementation": dielectric_brdf = dielectric_fresnel specular_brdf +
// (1 - max_value(dielectric_fresnel)) diffuse_brdf); the fit's Lambertian is not dimmed. Matching
// at normal incidence, where F is f0, keeps the colour a person sees face on in every channel.
void mapDiffuse(const fit::FittedMaterial& m, GltfMaterial& g, Losses& losses) {
  bool albedoClamped = false;
  const double f0Max = m.specularF0.maxChannel();
  for (std::size_t c = 0; c < 3; ++c) {
    double base = m.diffuseAlbedo[c] / std::max(1.0 - f0Max, kNegligible);
    if (base > 1.0) {
      albedoClamped = true;
      base = 1.0;
    }
    g.baseColorFactor[c] = base;
  }
  if (m.diffuseAlbedo.maxChannel() > kNegligible && f0Max > kNegligible)
    losses.push_back(
        {LossKind::DiffuseLayering,
         "glTF dims the diffuse by the specular's Fresnel (1 - max_value(F)); baseColorFactor is "
         "raised by 1 / (1 - max f0) = 1 / " + format(1.0 - f0Max) +
             " to match at normal incidence; toward grazing glTF's diffuse fades to (1 - F90) = " +
             format(1.0 - g.specularFactor) + " x the fit's"});
  if (albedoClamped)
    losses.push_back({LossKind::DiffuseLayering,
                      "diffuse albedo " + format(m.diffuseAlbedo.maxChannel()) +
                          " needs a baseColorFactor above 1: capped at 1"});
}

// The cosine-weighted mean over the hemisphere of E(mu), the directional albedo of the sheen lobe
// D_charlie / (4 (n.l + n.v - n.l n.v)) of alpha = sheenRoughnessFactor^2 (midpoint rules).
double sheenAlbedoMean(double sheenRoughnessFactor) {
  const double pi = std::numbers::pi;
  const double alpha = std::max(sheenRoughnessFactor * sheenRoughnessFactor, 1e-7);
  constexpr int kMu = 64, kTheta = 32, kPhi = 64;
  double mean = 0.0;
  for (int i = 0; i < kMu; ++i) {
    const double mu = (i + 0.5) / kMu, sinV = std::sqrt(1.0 - mu * mu);
    double albedo = 0.0;
    for (int t = 0; t < kTheta; ++t) {
      const double theta = (t + 0.5) * (pi / 2) / kTheta;
      const double cosL = std::cos(theta), sinL = std::sin(theta);
      for (int p = 0; p < kPhi; ++p) {
        const double phi = (p + 0.5) * 2 * pi / kPhi;
        const double hx = sinL * std::cos(phi) + sinV, hy = sinL * std::sin(phi), hz = cosL + mu;
        const double sin2h = 1.0 - hz * hz / (hx * hx + hy * hy + hz * hz);
        const double d = (2.0 + 1.0 / alpha) * std::pow(std::max(sin2h, 0.0), 0.5 / alpha) / (2.0 * pi);
        albedo += d / (4.0 * (cosL + mu - cosL * mu)) * cosL * sinL;
      }
    }
    mean += 2.0 * mu * albedo * (pi / 2 / kTheta) * (2 * pi / kPhi) / kMu;
  }
  return mean;
}

// KHR_materials_sheen scales the base by 1 - max(sheen) E(cos), E the sheen's directional
// albedo. Raising the base colour by that scaling at E's cosine-weighted mean over the
// hemisphere almost halves the loss on velvet-red: dE 3.10 unscaled, 2.68 matched face on (where
// E is smallest), 1.67 so (docs/material-export.md).
// E is the exporter's own (sheenAlbedoMean), not the check's (gltf_brdf.cpp), so that the check
// measures this choice instead of sharing it.
void raiseBaseUnderSheen(GltfMaterial& g) {
  const double meanAlbedo = sheenAlbedoMean(g.sheenRoughnessFactor);
  const double scaling = 1.0 - g.sheenColorFactor.maxChannel() * meanAlbedo;
  if (scaling > kNegligible)
    for (std::size_t c = 0; c < 3; ++c)
      g.baseColorFactor[c] = std::min(g.baseColorFactor[c] / scaling, 1.0);
}

// The sheen of a fit with one. The khr form is the extension's own layering: its colour and
// roughness are glTF's factors as they are (the fit bounds the colour to 1), the base colour
// stays as mapDiffuse set it. The additive form (format version 1) is not the extension's: its
// base colour is raised, which mapDiffuse set, as raiseBaseUnderSheen says.
void mapSheen(const fit::FittedMaterial& m, GltfMaterial& g, Losses& losses) {
  g.hasSheen = true;
  bool sheenClamped = false;
  for (std::size_t c = 0; c < 3; ++c) {
    g.sheenColorFactor[c] = std::min(m.sheenColour[c], 1.0);
    sheenClamped = sheenClamped || m.sheenColour[c] > 1.0;
  }
  // glTF's sheen D uses alpha = sheenRoughnessFactor^2 where the fit's lobe has exponent 1 / r.
  g.sheenRoughnessFactor = std::sqrt(m.sheenRoughness);
  if (sheenClamped)
    losses.push_back({LossKind::SheenForm,
                      "sheen colour " + format(m.sheenColour.maxChannel()) +
                          " above 1: sheenColorFactor capped at 1"});
  if (m.sheenForm == fit::SheenForm::Khr) return;
  losses.push_back(
      {LossKind::SheenForm,
       "KHR_materials_sheen dims the base layer by the sheen's directional albedo (up to " +
           format(g.sheenColorFactor.maxChannel()) +
           " x its albedo) and leaves the visibility term to the renderer; this fit (sheen_form "
           "additive, format version 1) adds its Charlie lobe on top with 1 / (4 (cos_i + cos_v - "
           "cos_i cos_v)): refit the table for the extension's layering"});
  raiseBaseUnderSheen(g);
}

// The coat of a "+coat" fit: the fit's coat is the extension's layering, only its roughness can
// exceed what the extension holds.
void mapCoat(const fit::FittedMaterial& m, GltfMaterial& g, Losses& losses) {
  g.hasClearcoat = true;
  g.clearcoatFactor = m.coatWeight;
  double alpha = m.coatAlpha;
  if (alpha > 1.0) {
    losses.push_back({LossKind::RoughnessClamped,
                      "coat alpha " + format(alpha) +
                          " > 1: clearcoatRoughnessFactor is capped at 1 (alpha 1)"});
    alpha = 1.0;
  }
  g.clearcoatRoughnessFactor = std::sqrt(alpha);
}

}  // namespace

GltfConversion toGltfMaterial(const fit::FittedMaterial& fitted) {
  const fit::FittedMaterial m = fitted.canonical();
  GltfConversion out;
  // The order matters: the diffuse needs the Fresnel's F90, the sheen the diffuse's base colour;
  // the losses come out in this order.
  mapLobe(m, out.material, out.losses);
  mapFresnel(m, out.material, out.losses);
  mapDiffuse(m, out.material, out.losses);
  if (fit::hasSheen(m.model)) mapSheen(m, out.material, out.losses);
  if (fit::hasCoat(m.model)) mapCoat(m, out.material, out.losses);
  return out;
}

}  // namespace slicecap::material_export
