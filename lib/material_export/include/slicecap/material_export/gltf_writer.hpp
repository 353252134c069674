// A glTF 2.0 asset of the fitted material on preview meshes: .gltf (JSON with the buffer embedded
// as a base64 data URI) or .glb (binary container).
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/material_export/conversion_loss.hpp"
#include "slicecap/material_export/gltf_material.hpp"

namespace slicecap::material_export {

/// \brief A glTF document and its one binary buffer (positions, normals, tangents, UVs, indices).
struct GltfAsset {
  nlohmann::ordered_json document;
  std::vector<std::uint8_t> buffer;
  ExportReport report;
};

/// \brief The glTF material object of `material` ("slicecap-fit": pbrMetallicRoughness with
/// metallicFactor 0 and the extensions it uses), as the asset writes it. Never throws.
nlohmann::ordered_json gltfMaterialJson(const GltfMaterial& material);

/// \brief The asset: a UV sphere and a cylinder side by side, both with the material
/// "slicecap-fit"; `source` (the table or material file) goes into asset.extras. Never throws.
GltfAsset gltfAsset(const fit::FittedMaterial& material, const std::string& source);

/// \brief The .gltf text: `asset` with its buffer as a data:application/octet-stream;base64 URI.
std::string gltfText(const GltfAsset& asset);

/// \brief The .glb bytes (glTF 2.0 binary container: header, JSON chunk, BIN chunk).
std::vector<std::uint8_t> glbBytes(const GltfAsset& asset);

/// \brief The file `path` gets for `asset`: the .glb bytes when it ends in ".glb" (any case), else
/// the .gltf text. Never throws.
std::string gltfFileContents(const GltfAsset& asset, const std::filesystem::path& path);

/// \brief Writes the asset to `path`, binary when it ends in ".glb" (any case), else .gltf text;
/// replaced whole through a temporary. Returns what the conversion lost. Throws io::IoError naming
/// the path when it cannot be written.
ExportReport writeGltf(const std::filesystem::path& path, const fit::FittedMaterial& material,
                       const std::string& source);

/// \brief Standard base64 (RFC 4648, with padding) of `bytes`.
std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace slicecap::material_export
