// glTF's BRDF from its factors (KHR_materials_anisotropy README, "Implementation"; KHR_materials_
// specular README, "Implementation"; KHR_materials_sheen, the albedo scaling; KHR_materials_
// clearcoat, "Layering"), for measuring the glTF export against the fit.
#include "slicecap/material_export/gltf_brdf.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace slicecap::material_export {
namespace {

double dot(const UnitVector& a, const UnitVector& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

UnitVector halfVector(const UnitVector& l, const UnitVector& v) {
  const double x = l.x + v.x, y = l.y + v.y, z = l.z + v.z;
  const double n = std::sqrt(x * x + y * y + z * z);
  return {x / n, y / n, z / n};
}

// KHR_materials_anisotropy's D_GGX_anisotropic V_GGX_anisotropic: alpha `at` along the unit
// tangent t, `ab` along the bitangent b (both in the surface). With at = ab (any t, b) it is glTF
// 2.0 Appendix B's isotropic D V, the clear coat's lobe.
double ggxLobe(const UnitVector& l, const UnitVector& v, const UnitVector& h, const UnitVector& t,
               const UnitVector& b, double at, double ab) {
  const double a2 = at * ab;
  const double fx = ab * dot(t, h), fy = at * dot(b, h), fz = a2 * h.z;
  const double w2 = a2 / (fx * fx + fy * fy + fz * fz);
  const double d = a2 * w2 * w2 / std::numbers::pi;
  const double lengthV = std::sqrt(std::pow(at * dot(t, v), 2) + std::pow(ab * dot(b, v), 2) + v.z * v.z);
  const double lengthL = std::sqrt(std::pow(at * dot(t, l), 2) + std::pow(ab * dot(b, l), 2) + l.z * l.z);
  return d * 0.5 / (l.z * lengthV + v.z * lengthL);
}

}  // namespace

GltfBrdf::GltfBrdf(const GltfMaterial& material) : material_(material) {
  if (!material_.hasSheen) return;
  // E(mu) = integral over the hemisphere of D_sheen V cos(theta_l): the energy the sheen takes,
  // which glTF removes from the base layer.
  constexpr int kTheta = 32, kPhi = 64;
  const double pi = std::numbers::pi;
  for (int i = 0; i < kAlbedoSamples; ++i) {
    const double mu = std::max(static_cast<double>(i) / (kAlbedoSamples - 1), 1e-3);
    const UnitVector v{std::sqrt(1.0 - mu * mu), 0.0, mu};
    double sum = 0.0;
    for (int t = 0; t < kTheta; ++t) {
      const double theta = (t + 0.5) * (pi / 2) / kTheta;
      for (int p = 0; p < kPhi; ++p) {
        const double phi = (p + 0.5) * 2 * pi / kPhi;
        const UnitVector l{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                           std::cos(theta)};
        sum += sheenLobe(l, v) * l.z * std::sin(theta);
      }
    }
    sheenAlbedo_[static_cast<std::size_t>(i)] = sum * (pi / 2 / kTheta) * (2 * pi / kPhi);
  }
}

double GltfBrdf::sheenLobe(const UnitVector& l, const UnitVector& v) const {
  const UnitVector h = halfVector(l, v);
  const double alpha = std::max(material_.sheenRoughnessFactor * material_.sheenRoughnessFactor, 1e-7);
  const double sinTheta = std::sqrt(std::max(1.0 - h.z * h.z, 0.0));
  const double d = (2.0 + 1.0 / alpha) * std::pow(sinTheta, 1.0 / alpha) / (2.0 * std::numbers::pi);
  return d / (4.0 * (l.z + v.z - l.z * v.z));
}

double GltfBrdf::sheenAlbedo(double cosTheta) const {
  const double at = std::clamp(cosTheta, 0.0, 1.0) * (kAlbedoSamples - 1);
  const auto i = std::min(static_cast<std::size_t>(at), static_cast<std::size_t>(kAlbedoSamples - 2));
  const double f = at - static_cast<double>(i);
  return sheenAlbedo_[i] * (1.0 - f) + sheenAlbedo_[i + 1] * f;
}

Rgb GltfBrdf::evaluate(const UnitVector& l, const UnitVector& v) const {
  const GltfMaterial& g = material_;
  const UnitVector h = halfVector(l, v);
  // The anisotropy direction: TANGENT (x) turned by anisotropyRotation toward the bitangent (y).
  const UnitVector t{std::cos(g.anisotropyRotationRad), std::sin(g.anisotropyRotationRad), 0.0};
  const UnitVector b{-t.y, t.x, 0.0};
  const double alpha = g.roughnessFactor * g.roughnessFactor;
  const double s2 = g.anisotropyStrength * g.anisotropyStrength;
  const double at = std::max(alpha * (1.0 - s2) + s2, 1e-7), ab = std::max(alpha, 1e-7);
  const double lobe = ggxLobe(l, v, h, t, b, at, ab);
  const double iorF0 = std::pow((g.ior - 1.0) / (g.ior + 1.0), 2);
  const double weight = std::pow(1.0 - std::clamp(dot(v, h), 0.0, 1.0), 5.0);

  double scaling = 1.0, sheen = 0.0;
  if (g.hasSheen) {
    const double brightest = g.sheenColorFactor.maxChannel();
    scaling = std::min(1.0 - brightest * sheenAlbedo(v.z), 1.0 - brightest * sheenAlbedo(l.z));
    sheen = sheenLobe(l, v);
  }
  Rgb out;
  for (std::size_t c = 0; c < 3; ++c) {
    const double f0 = std::min(iorF0 * g.specularColorFactor[c], 1.0) * g.specularFactor;
    const double fresnel = f0 + (g.specularFactor - f0) * weight;
    const double base = g.baseColorFactor[c] / std::numbers::pi * (1.0 - fresnel) + fresnel * lobe;
    out[c] = g.sheenColorFactor[c] * sheen + scaling * base;
  }
  if (g.hasClearcoat) {
    const double coatFresnel =
        fit::kCoatF0 + (1.0 - fit::kCoatF0) * std::pow(1.0 - std::clamp(v.z, 0.0, 1.0), 5.0);
    const double share = g.clearcoatFactor * coatFresnel;
    const double coatAlpha = std::max(std::pow(g.clearcoatRoughnessFactor, 2), 1e-7);
    const double coat = ggxLobe(l, v, h, t, b, coatAlpha, coatAlpha);
    for (std::size_t c = 0; c < 3; ++c) out[c] = out[c] * (1.0 - share) + share * coat;
  }
  return out;
}

Abrdf tabulate(const GltfBrdf& brdf) {
  return tabulateOnGrid([&brdf](const UnitVector& l, const UnitVector& v) { return brdf.evaluate(l, v); });
}

eval::Metrics gltfVersusFit(const fit::FittedMaterial& fitted) {
  return eval::compare(fit::tabulate(fitted), tabulate(GltfBrdf(toGltfMaterial(fitted).material)));
}

}  // namespace slicecap::material_export
