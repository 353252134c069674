// A texture fit as glTF's texture maps (docs/material-fit.md "Texture mode"): base colour,
// metallic-roughness, KHR_materials_anisotropy's direction + strength, KHR_materials_specular's
// colour + factor, the normal map of the fitted tilts and the mask of texels that could not be
// fitted.
#pragma once

#include <map>
#include <string>

#include "slicecap/core/image.hpp"
#include "slicecap/fit/texture_fit.hpp"
#include "slicecap/material_export/conversion_loss.hpp"

namespace slicecap::material_export {

/// \brief The maps, 8-bit, N x N, row 0 = the texture's row 0 (the window's top), as glTF samples
/// them (UV (0, 0) at the image's top-left). Per texel the factors of toGltfMaterial, except the
/// IOR, which glTF cannot texture: one IOR for the whole material, chosen so that every texel's
/// F0 / F90 fits in specularColorTexture (<= 1).
struct GltfTextureMaps {
  Image baseColor;          ///< RGB, sRGB-encoded: baseColorFactor per texel
  Image metallicRoughness;  ///< RGB, linear: G = roughness (sqrt of alpha across), B = metallic 0
  Image anisotropy;         ///< RGB, linear: RG = direction (cos, sin) * 0.5 + 0.5, B = strength
  Image specular;           ///< RGBA: RGB = specularColor (sRGB), A = specularFactor (linear)
  Image normal;  ///< RGB, linear: glTF normalTexture, (n + 1) / 2 of TexelFit::shadingNormal
                 ///< (x = TANGENT, y = bitangent); (0, 0, 1) where the tilt is flat or unfitted
  Image mask;               ///< gray: 255 fitted, 0 not (named in the fit's TexelFit::problem)
  double ior = 1.5;         ///< KHR_materials_ior for the whole material
  /// \brief Conversion losses over the fitted texels: per kind, how many texels had it.
  std::map<LossKind, std::size_t> lossCounts;
};

/// \brief The maps of a texture fit. Never throws. A texel that was not fitted is black, roughness
/// 1, no anisotropy, no specular, and 0 in the mask.
GltfTextureMaps gltfTextureMaps(const fit::TextureFitResult& fit);

/// \brief 8-bit sRGB encoding of a linear value (clamped to [0, 1]).
std::uint16_t srgb8(double linear);
/// \brief 8-bit linear encoding of a value in [0, 1] (clamped).
std::uint16_t linear8(double value);

}  // namespace slicecap::material_export
