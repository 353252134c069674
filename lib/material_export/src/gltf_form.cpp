// The choice between glTF's dielectric + specular form and the metal blend, by the specification's
// BRDF and by the per-channel reading three.js 0.187 draws (docs/results/2026-12-06-export-spec.md,
// "three.js r187 against the specification").
#include "slicecap/material_export/gltf_form.hpp"

#include <algorithm>
#include <sstream>
#include <string>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/material_export/gltf_brdf.hpp"
#include "slicecap/material_export/gltf_writer.hpp"
#include "loss_text.hpp"

namespace slicecap::material_export {
namespace {

// Below this a channel difference or an albedo is none (the fit's bounds reach exactly 0).
constexpr double kNegligible = 1e-6;

std::string format(double v) { return detail::lossFigure(v); }

std::string format(const Rgb& c) { return format(c[0]) + "/" + format(c[1]) + "/" + format(c[2]); }

// Only here do the two readings differ: a diffuse under a specular whose channels differ.
bool readingsCanDiffer(const fit::FittedMaterial& m) {
  const double f0Max = m.specularF0.maxChannel();
  const double f0Min = std::min({m.specularF0[0], m.specularF0[1], m.specularF0[2]});
  return m.diffuseAlbedo.maxChannel() > kNegligible && f0Max - f0Min > kNegligible;
}

double deltaE(const Abrdf& fitTable, const GltfMaterial& g, DiffuseDimming dimming) {
  return eval::compare(fitTable, tabulate(GltfBrdf(gltfMaterialJson(g), SheenVisibility::Charlie,
                                                   dimming)))
      .deltaE;
}

}  // namespace

GltfMaterial metalBlend(const fit::FittedMaterial& fitted) {
  const fit::FittedMaterial m = fitted.canonical();
  GltfMaterial g = toGltfMaterial(m).material;
  double f0Sum = 0.0, diffuseSum = 0.0;
  for (std::size_t c = 0; c < 3; ++c) {
    f0Sum += m.specularF0[c];
    diffuseSum += m.diffuseAlbedo[c];
  }
  g.metallicFactor = f0Sum + diffuseSum > kNegligible ? f0Sum / (f0Sum + diffuseSum) : 0.0;
  for (std::size_t c = 0; c < 3; ++c)
    g.baseColorFactor[c] =
        g.metallicFactor > kNegligible ? std::min(m.specularF0[c] / g.metallicFactor, 1.0) : 0.0;
  g.specularFactor = 0.0;
  g.specularColorFactor = Rgb::gray(1.0);
  g.ior = 1.5;
  return g;
}

GltfConversion chooseGltfForm(const fit::FittedMaterial& fitted) {
  GltfConversion dielectric = toGltfMaterial(fitted);
  const fit::FittedMaterial m = fitted.canonical();
  if (!readingsCanDiffer(m)) return dielectric;
  const Abrdf fitTable = fit::tabulate(m);
  const double bySpec = deltaE(fitTable, dielectric.material, DiffuseDimming::MaxValue);
  const double perChannel = deltaE(fitTable, dielectric.material, DiffuseDimming::PerChannel);
  GltfConversion blend{metalBlend(m), {}};
  // Both readings draw the blend alike: its dielectric specular is 0, so nothing dims the diffuse.
  const double blendDeltaE = deltaE(fitTable, blend.material, DiffuseDimming::MaxValue);
  const std::string figures = "dE by the specification: dielectric form " + format(bySpec) +
                              ", read per channel " + format(perChannel) + "; metal blend " +
                              format(blendDeltaE);
  if (blendDeltaE <= kGltfSpecGoalDeltaE && blendDeltaE < std::max(bySpec, perChannel)) {
    for (const ConversionLoss& loss : dielectric.losses)
      if (loss.kind != LossKind::DiffuseLayering) blend.losses.push_back(loss);
    Rgb diffuse;
    for (std::size_t c = 0; c < 3; ++c)
      diffuse[c] = (1.0 - blend.material.metallicFactor) * blend.material.baseColorFactor[c];
    blend.losses.push_back(
        {LossKind::DiffuseLayering,
         "coloured specular over a diffuse, exported as a metal blend (metallicFactor " +
             format(blend.material.metallicFactor) +
             ", baseColorFactor f0 / metallicFactor, specularFactor 0) that renderers dimming the "
             "diffuse by 1 - max_value(F) (the specification) or per channel (three.js 0.187) "
             "draw alike: diffuse " + format(diffuse) + " for the fit's " +
             format(m.diffuseAlbedo) + ", F90 " + format(blend.material.metallicFactor) + "; " +
             figures});
    return blend;
  }
  dielectric.losses.push_back(
      {LossKind::DiffuseLayering,
       "a renderer that dims each channel's diffuse by its own 1 - F (three.js 0.187, not the "
       "specification) draws this coloured specular's diffuse differently; " + figures +
           " (kept: the blend is above " + format(kGltfSpecGoalDeltaE) +
           " or no nearer)"});
  return dielectric;
}

}  // namespace slicecap::material_export
