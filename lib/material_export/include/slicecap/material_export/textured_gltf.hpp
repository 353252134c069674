// The SVBRDF maps of a texture fit on disk: the PNG textures and a glTF 2.0 material that
// references them on a plane with tangents (docs/material-fit.md "Texture mode").
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slicecap/io/file_set.hpp"
#include "slicecap/material_export/texture_maps.hpp"

namespace slicecap::material_export {

/// \brief The files writeTexturedGltf writes in its directory.
inline constexpr const char* kBaseColorPng = "base_color.png";
inline constexpr const char* kMetallicRoughnessPng = "metallic_roughness.png";
inline constexpr const char* kAnisotropyPng = "anisotropy.png";
inline constexpr const char* kSpecularPng = "specular.png";
inline constexpr const char* kNormalPng = "normal.png";
inline constexpr const char* kMaskPng = "mask.png";
inline constexpr const char* kTexturedGltf = "material.gltf";

/// \brief The glTF document (buffer embedded as a data URI, images by relative URI) of a plane
/// `widthM` x `heightM` in the x-y plane facing +z, TANGENT +x (the texture's azimuth-0 axis),
/// bitangent +y (w = +1), UV (0, 0) at its top-left corner (the texture's row 0, column 0), with
/// the material "slicecap-svbrdf" using the maps. `source` goes into asset.extras. Never throws.
nlohmann::ordered_json texturedGltfDocument(const GltfTextureMaps& maps, double widthM,
                                            double heightM, const std::string& source);

/// \brief The six PNGs and material.gltf as members of a file set (io::replaceFileSet), for the
/// caller to write with its own files as one. The entries refer to `maps`, which must outlive
/// them. Never throws; each entry's writer throws io::IoError naming its file.
std::vector<io::FileSetEntry> texturedGltfFiles(const GltfTextureMaps& maps, double widthM,
                                                double heightM, const std::string& source);

}  // namespace slicecap::material_export
