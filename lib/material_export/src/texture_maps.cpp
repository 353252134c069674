// Per texel the glTF factors of toGltfMaterial, packed as glTF's textures expect them
// (glTF 2.0 "Materials"; KHR_materials_anisotropy, KHR_materials_specular READMEs).
#include "slicecap/material_export/texture_maps.hpp"

#include <algorithm>
#include <cmath>

#include "slicecap/material_export/gltf_material.hpp"

namespace slicecap::material_export {
namespace {

Image blank(int size, int channels) {
  Image image;
  image.width = image.height = size;
  image.channels = channels;
  image.bitDepth = 8;
  image.samples.assign(std::size_t(size) * std::size_t(size) * std::size_t(channels), 0);
  return image;
}

double f0OfIor(double ior) { return std::pow((ior - 1.0) / (ior + 1.0), 2); }

// As gltf_material.cpp: F0 0.9 (IOR 37.97) is the brightest an IOR is asked to carry.
constexpr double kMaxIorF0 = 0.9;

}  // namespace

std::uint16_t srgb8(double linear) {
  const double x = std::clamp(linear, 0.0, 1.0);
  const double encoded = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
  return static_cast<std::uint16_t>(std::lround(255.0 * encoded));
}

std::uint16_t linear8(double value) {
  return static_cast<std::uint16_t>(std::lround(255.0 * std::clamp(value, 0.0, 1.0)));
}

GltfTextureMaps gltfTextureMaps(const fit::TextureFitResult& fit) {
  const int n = fit.resolution;
  GltfTextureMaps maps;
  maps.baseColor = blank(n, 3);
  maps.metallicRoughness = blank(n, 3);
  maps.anisotropy = blank(n, 3);
  maps.specular = blank(n, 4);
  maps.normal = blank(n, 3);
  maps.mask = blank(n, 1);

  // Per texel the F0 / F90 ratio glTF carries as F0(ior) * specularColor; the IOR shared by all.
  std::vector<GltfConversion> conversions(fit.texels.size());
  double brightestRatio = 0.0;
  for (std::size_t i = 0; i < fit.texels.size(); ++i) {
    if (fit.texels[i].status != fit::TexelStatus::Fitted) continue;
    conversions[i] = toGltfMaterial(fit.texels[i].material);
    const GltfMaterial& g = conversions[i].material;
    brightestRatio = std::max(brightestRatio, f0OfIor(g.ior) * g.specularColorFactor.maxChannel());
    for (const ConversionLoss& loss : conversions[i].losses) ++maps.lossCounts[loss.kind];
  }
  const double iorF0 = std::min(brightestRatio, kMaxIorF0);
  maps.ior = iorF0 > 1e-6 ? (1.0 + std::sqrt(iorF0)) / (1.0 - std::sqrt(iorF0)) : 1.0;

  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(n) + std::size_t(x);
      maps.metallicRoughness.at(x, y, 1) = 255;  // an unfitted texel: roughness 1, no specular
      // glTF's normalTexture: RGB = (n + 1) / 2 of the tangent-space normal, x along TANGENT (the
      // texel frame's x), y along cross(NORMAL, TANGENT) * w (its y); flat where not fitted.
      const UnitVector normal = fit.texels[i].status == fit::TexelStatus::Fitted
                                    ? fit.texels[i].shadingNormal
                                    : UnitVector{};
      maps.normal.at(x, y, 0) = linear8(0.5 + 0.5 * normal.x);
      maps.normal.at(x, y, 1) = linear8(0.5 + 0.5 * normal.y);
      maps.normal.at(x, y, 2) = linear8(0.5 + 0.5 * normal.z);
      if (fit.texels[i].status != fit::TexelStatus::Fitted) continue;
      const GltfMaterial& g = conversions[i].material;
      maps.mask.at(x, y, 0) = 255;
      const double ratioScale = iorF0 > 1e-6 ? f0OfIor(g.ior) / iorF0 : 0.0;
      for (int c = 0; c < 3; ++c) {
        maps.baseColor.at(x, y, c) = srgb8(g.baseColorFactor[std::size_t(c)]);
        maps.specular.at(x, y, c) = srgb8(g.specularColorFactor[std::size_t(c)] * ratioScale);
      }
      maps.specular.at(x, y, 3) = linear8(g.specularFactor);
      maps.metallicRoughness.at(x, y, 1) = linear8(g.roughnessFactor);
      maps.anisotropy.at(x, y, 0) = linear8(0.5 + 0.5 * std::cos(g.anisotropyRotationRad));
      maps.anisotropy.at(x, y, 1) = linear8(0.5 + 0.5 * std::sin(g.anisotropyRotationRad));
      maps.anisotropy.at(x, y, 2) = linear8(g.anisotropyStrength);
    }
  return maps;
}

}  // namespace slicecap::material_export
