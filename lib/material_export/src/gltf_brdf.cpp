// glTF's BRDF of a material object as the specifications write it (glTF 2.0 Appendix B;
// KHR_materials_anisotropy, _specular, _ior, _sheen and _clearcoat READMEs, "Implementation"),
// for measuring the glTF export against the fit. Written from those texts only: nothing here is
// shared with the exporter's mapping (gltf_material.cpp).
#include "slicecap/material_export/gltf_brdf.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "slicecap/material_export/gltf_form.hpp"
#include "slicecap/material_export/gltf_material.hpp"
#include "slicecap/material_export/gltf_writer.hpp"

namespace slicecap::material_export {
namespace {

using json = nlohmann::ordered_json;
constexpr double kPi = std::numbers::pi;

double dot(const UnitVector& a, const UnitVector& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

UnitVector halfVector(const UnitVector& l, const UnitVector& v) {
  const double x = l.x + v.x, y = l.y + v.y, z = l.z + v.z;
  const double n = std::sqrt(x * x + y * y + z * z);
  return {x / n, y / n, z / n};
}

double mix(double x, double y, double a) { return x * (1.0 - a) + y * a; }

// The object at `key` of `parent` (a glTF "extensions" entry or pbrMetallicRoughness), or null.
const json* member(const json& parent, const char* key) {
  if (!parent.is_object()) return nullptr;
  const auto it = parent.find(key);
  return it == parent.end() ? nullptr : &*it;
}

double number(const json* object, const char* key, double fallback, const std::string& where) {
  const json* value = object ? member(*object, key) : nullptr;
  if (!value) return fallback;
  if (!value->is_number()) throw GltfMaterialError(where + "." + key + " is not a number");
  return value->get<double>();
}

// An RGB factor (the first three of baseColorFactor's four).
Rgb colour(const json* object, const char* key, const Rgb& fallback, std::size_t size,
           const std::string& where) {
  const json* value = object ? member(*object, key) : nullptr;
  if (!value) return fallback;
  if (!value->is_array() || value->size() != size)
    throw GltfMaterialError(where + "." + key + " is not an array of " + std::to_string(size) +
                            " numbers");
  Rgb out;
  for (std::size_t c = 0; c < 3; ++c) {
    if (!(*value)[c].is_number())
      throw GltfMaterialError(where + "." + key + "[" + std::to_string(c) + "] is not a number");
    out[c] = (*value)[c].get<double>();
  }
  return out;
}

// KHR_materials_anisotropy's D_GGX_anisotropic V_GGX_anisotropic: alpha `at` along the unit
// tangent t, `ab` along the bitangent b. With at = ab it is Appendix B's isotropic V D.
double ggxLobe(const UnitVector& l, const UnitVector& v, const UnitVector& h, const UnitVector& t,
               const UnitVector& b, double at, double ab) {
  const double a2 = at * ab;
  const double fx = ab * dot(t, h), fy = at * dot(b, h), fz = a2 * h.z;
  const double w2 = a2 / (fx * fx + fy * fy + fz * fz);
  const double d = a2 * w2 * w2 / kPi;
  const double ggxV = l.z * std::sqrt(std::pow(at * dot(t, v), 2) + std::pow(ab * dot(b, v), 2) + v.z * v.z);
  const double ggxL = v.z * std::sqrt(std::pow(at * dot(t, l), 2) + std::pow(ab * dot(b, l), 2) + l.z * l.z);
  return d * 0.5 / (ggxV + ggxL);
}

// KHR_materials_sheen, "Sheen visibility": the Charlie visibility's lambda (Estevez and Kulla).
double sheenL(double x, double alphaG) {
  const double oneMinusAlphaSq = (1.0 - alphaG) * (1.0 - alphaG);
  const double a = mix(21.5473, 25.3245, oneMinusAlphaSq);
  const double b = mix(3.82987, 3.32435, oneMinusAlphaSq);
  const double c = mix(0.19823, 0.16801, oneMinusAlphaSq);
  const double d = mix(-1.97760, -1.27393, oneMinusAlphaSq);
  const double e = mix(-4.32054, -4.85967, oneMinusAlphaSq);
  return a / (1.0 + b * std::pow(x, c)) + d * x + e;
}

double lambdaSheen(double cosTheta, double alphaG) {
  return std::abs(cosTheta) < 0.5
             ? std::exp(sheenL(cosTheta, alphaG))
             : std::exp(2.0 * sheenL(0.5, alphaG) - sheenL(1.0 - cosTheta, alphaG));
}

}  // namespace

GltfBrdf::GltfBrdf(const json& material, SheenVisibility visibility, DiffuseDimming dimming)
    : visibility_(visibility), dimming_(dimming) {
  const std::string where = "material";
  const json* pbr = member(material, "pbrMetallicRoughness");
  const json* extensions = member(material, "extensions");
  const auto extension = [&](const char* name) { return extensions ? member(*extensions, name) : nullptr; };
  const std::string pbrWhere = where + ".pbrMetallicRoughness";
  f_.baseColor = colour(pbr, "baseColorFactor", Rgb::gray(1.0), 4, pbrWhere);
  f_.metallic = number(pbr, "metallicFactor", 1.0, pbrWhere);
  f_.roughness = number(pbr, "roughnessFactor", 1.0, pbrWhere);
  const json* anisotropy = extension("KHR_materials_anisotropy");
  f_.anisotropyStrength = number(anisotropy, "anisotropyStrength", 0.0, "KHR_materials_anisotropy");
  f_.anisotropyRotationRad = number(anisotropy, "anisotropyRotation", 0.0, "KHR_materials_anisotropy");
  const json* specular = extension("KHR_materials_specular");
  f_.specular = number(specular, "specularFactor", 1.0, "KHR_materials_specular");
  f_.specularColor = colour(specular, "specularColorFactor", Rgb::gray(1.0), 3, "KHR_materials_specular");
  f_.ior = number(extension("KHR_materials_ior"), "ior", 1.5, "KHR_materials_ior");
  const json* sheen = extension("KHR_materials_sheen");
  f_.sheenColor = colour(sheen, "sheenColorFactor", Rgb{}, 3, "KHR_materials_sheen");
  f_.sheenRoughness = number(sheen, "sheenRoughnessFactor", 0.0, "KHR_materials_sheen");
  const json* clearcoat = extension("KHR_materials_clearcoat");
  f_.clearcoat = number(clearcoat, "clearcoatFactor", 0.0, "KHR_materials_clearcoat");
  f_.clearcoatRoughness = number(clearcoat, "clearcoatRoughnessFactor", 0.0, "KHR_materials_clearcoat");

  if (f_.sheenColor.maxChannel() <= 0.0) return;  // "If sheenColorFactor is zero, the whole sheen layer is disabled"
  // E(mu) = integral over the hemisphere of D_sheen V_sheen cos(theta_l): the sheen's directional
  // albedo, which the extension's albedo scaling removes from the base.
  constexpr int kTheta = 32, kPhi = 64;
  for (int i = 0; i < kAlbedoSamples; ++i) {
    const double mu = std::max(static_cast<double>(i) / (kAlbedoSamples - 1), 1e-3);
    const UnitVector v{std::sqrt(1.0 - mu * mu), 0.0, mu};
    double sum = 0.0;
    for (int t = 0; t < kTheta; ++t) {
      const double theta = (t + 0.5) * (kPi / 2) / kTheta;
      for (int p = 0; p < kPhi; ++p) {
        const double phi = (p + 0.5) * 2 * kPi / kPhi;
        const UnitVector l{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                           std::cos(theta)};
        sum += sheenLobe(l, v) * l.z * std::sin(theta);
      }
    }
    sheenAlbedo_[static_cast<std::size_t>(i)] = sum * (kPi / 2 / kTheta) * (2 * kPi / kPhi);
  }
}

double GltfBrdf::sheenLobe(const UnitVector& l, const UnitVector& v) const {
  const UnitVector h = halfVector(l, v);
  // "Sheen distribution": alpha_g = sheenRoughness^2 (floored: 1 / alpha_g is an exponent).
  const double alphaG = std::max(f_.sheenRoughness * f_.sheenRoughness, 1e-7);
  const double invR = 1.0 / alphaG;
  const double sin2h = std::max(1.0 - h.z * h.z, 0.0);
  const double d = (2.0 + invR) * std::pow(sin2h, invR * 0.5) / (2.0 * kPi);
  const double visibility =
      visibility_ == SheenVisibility::Charlie
          ? 1.0 / ((1.0 + lambdaSheen(v.z, alphaG) + lambdaSheen(l.z, alphaG)) * (4.0 * v.z * l.z))
          : 1.0 / (4.0 * (l.z + v.z - l.z * v.z));
  return d * visibility;
}

double GltfBrdf::sheenAlbedo(double cosTheta) const {
  const double at = std::clamp(cosTheta, 0.0, 1.0) * (kAlbedoSamples - 1);
  const auto i = std::min(static_cast<std::size_t>(at), static_cast<std::size_t>(kAlbedoSamples - 2));
  const double f = at - static_cast<double>(i);
  return sheenAlbedo_[i] * (1.0 - f) + sheenAlbedo_[i + 1] * f;
}

Rgb GltfBrdf::evaluate(const UnitVector& l, const UnitVector& v) const {
  const UnitVector h = halfVector(l, v);
  // The anisotropy direction: TANGENT (x) turned by anisotropyRotation toward the bitangent (y).
  const UnitVector t{std::cos(f_.anisotropyRotationRad), std::sin(f_.anisotropyRotationRad), 0.0};
  const UnitVector b{-t.y, t.x, 0.0};
  const double alpha = f_.roughness * f_.roughness;
  const double s2 = f_.anisotropyStrength * f_.anisotropyStrength;
  const double at = std::max(mix(alpha, 1.0, s2), 1e-7), ab = std::max(alpha, 1e-7);
  const double specularBrdf = ggxLobe(l, v, h, t, b, at, ab);
  const double vDotH = std::abs(dot(v, h));
  const double fresnelW = std::pow(1.0 - vDotH, 5.0);
  const double iorF0 = std::pow((f_.ior - 1.0) / (f_.ior + 1.0), 2);

  Rgb dielectricFresnel;
  for (std::size_t c = 0; c < 3; ++c)
    dielectricFresnel[c] =
        mix(std::min(iorF0 * f_.specularColor[c], 1.0) * f_.specular, f_.specular, fresnelW);
  const double dielectricFresnelMax = dielectricFresnel.maxChannel();

  double sheenScaling = 1.0, sheen = 0.0;
  const double sheenMax = f_.sheenColor.maxChannel();
  if (sheenMax > 0.0) {
    sheenScaling = std::min(1.0 - sheenMax * sheenAlbedo(v.z), 1.0 - sheenMax * sheenAlbedo(l.z));
    sheen = sheenLobe(l, v);
  }
  const double coatFresnel = 0.04 + (1.0 - 0.04) * std::pow(1.0 - std::abs(v.z), 5.0);
  const double coatShare = f_.clearcoat * coatFresnel;
  const double coatAlpha = std::max(f_.clearcoatRoughness * f_.clearcoatRoughness, 1e-7);
  const double coatBrdf = coatShare > 0.0 ? ggxLobe(l, v, h, t, b, coatAlpha, coatAlpha) : 0.0;

  Rgb out;
  for (std::size_t c = 0; c < 3; ++c) {
    const double diffuse = f_.baseColor[c] / kPi;
    const double dimmedBy =
        dimming_ == DiffuseDimming::MaxValue ? dielectricFresnelMax : dielectricFresnel[c];
    const double dielectric = dielectricFresnel[c] * specularBrdf + (1.0 - dimmedBy) * diffuse;
    const double metal =
        specularBrdf * (f_.baseColor[c] + (1.0 - f_.baseColor[c]) * fresnelW);
    const double material = mix(dielectric, metal, f_.metallic);
    const double sheenMaterial = f_.sheenColor[c] * sheen + material * sheenScaling;
    out[c] = mix(sheenMaterial, coatBrdf, coatShare);
  }
  return out;
}

Abrdf tabulate(const GltfBrdf& brdf) {
  return tabulateOnGrid([&brdf](const UnitVector& l, const UnitVector& v) { return brdf.evaluate(l, v); });
}

bool gltfVersusFitExists(const fit::FittedMaterial& fitted) {
  return eval::canCompareAgainst(fit::tabulate(fitted));
}

eval::Metrics gltfVersusFit(const fit::FittedMaterial& fitted, SheenVisibility visibility) {
  const GltfBrdf brdf(gltfMaterialJson(chooseGltfForm(fitted).material), visibility);
  return eval::compare(fit::tabulate(fitted), tabulate(brdf));
}

}  // namespace slicecap::material_export
