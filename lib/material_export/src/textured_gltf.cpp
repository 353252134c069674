// A plane carrying the texture fit's maps as a glTF 2.0 material (glTF 2.0 "Materials",
// "Textures"; KHR_materials_anisotropy, _specular, _ior READMEs).
#include "slicecap/material_export/textured_gltf.hpp"

#include <array>
#include <cstring>
#include <ostream>
#include <vector>

#include "gltf_buffer.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/material_export/gltf_writer.hpp"

namespace slicecap::material_export {
namespace {

using json = nlohmann::ordered_json;

constexpr int kLinear = 9729, kLinearMipmapLinear = 9987, kClampToEdge = 33071;

using namespace gltf_buffer;

json textureRef(int index) { return {{"index", index}}; }

json materialJson(const GltfTextureMaps& maps) {
  // Texture indices follow the images' order in texturedGltfDocument.
  return {{"name", "slicecap-svbrdf"},
          {"pbrMetallicRoughness",
           {{"baseColorTexture", textureRef(0)},
            {"metallicFactor", 0.0},
            {"roughnessFactor", 1.0},
            {"metallicRoughnessTexture", textureRef(1)}}},
          {"normalTexture", textureRef(4)},
          {"extensions",
           {{"KHR_materials_anisotropy",
             {{"anisotropyStrength", 1.0}, {"anisotropyRotation", 0.0},
              {"anisotropyTexture", textureRef(2)}}},
            {"KHR_materials_specular",
             {{"specularFactor", 1.0}, {"specularTexture", textureRef(3)},
              {"specularColorFactor", {1.0, 1.0, 1.0}}, {"specularColorTexture", textureRef(3)}}},
            {"KHR_materials_ior", {{"ior", maps.ior}}}}}};
}

json lossesJson(const GltfTextureMaps& maps) {
  json losses = json::object();
  for (const auto& [kind, texels] : maps.lossCounts) losses[std::string(toString(kind))] = texels;
  return losses;
}

}  // namespace

json texturedGltfDocument(const GltfTextureMaps& maps, double widthM, double heightM,
                          const std::string& source) {
  const auto w = static_cast<float>(widthM / 2), h = static_cast<float>(heightM / 2);
  // The plane's four corners: position, normal, tangent, UV (v grows downward in the image, so
  // toward -y).
  using Vec2 = std::array<float, 2>;
  using Vec3 = std::array<float, 3>;
  using Vec4 = std::array<float, 4>;
  BufferBuilder buffer;
  buffer.addVectors(std::vector<Vec3>{{-w, h, 0}, {w, h, 0}, {w, -h, 0}, {-w, -h, 0}}, kFloat,
                    "VEC3", true);
  buffer.addVectors(std::vector<Vec3>(4, Vec3{0, 0, 1}), kFloat, "VEC3", false);
  buffer.addVectors(std::vector<Vec4>(4, Vec4{1, 0, 0, 1}), kFloat, "VEC4", false);
  buffer.addVectors(std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, kFloat, "VEC2", false);
  buffer.addIndices({0, 3, 2, 0, 2, 1});  // counter-clockwise seen from +z

  json images = json::array();
  for (const char* file : {kBaseColorPng, kMetallicRoughnessPng, kAnisotropyPng, kSpecularPng, kNormalPng})
    images.push_back({{"uri", file}, {"mimeType", "image/png"}});
  json textures = json::array();
  for (std::size_t i = 0; i < images.size(); ++i) textures.push_back({{"sampler", 0}, {"source", i}});

  return {
      {"asset",
       {{"version", "2.0"},
        {"generator", std::string("slicecap ") + kVersion},
        {"extras",
         {{"slicecap_source", source},
          {"slicecap_conventions",
           "per-texel material fitted by slicecap fit (docs/material-fit.md, Texture mode); TANGENT "
           "is the texture's azimuth-0 axis (+x), anisotropyTexture RG the fitted tangent in "
           "tangent/bitangent space; normal.png the fitted shading normal (x along TANGENT, y "
           "along the bitangent; flat where the lobe could not locate it, named in maps.json); "
           "mask.png (beside this file) is 0 where a texel could not be fitted"},
          {"slicecap_conversion_losses_texels", lossesJson(maps)}}}}},
      {"extensionsUsed", {"KHR_materials_anisotropy", "KHR_materials_specular", "KHR_materials_ior"}},
      {"scene", 0},
      {"scenes", {{{"name", "slicecap svbrdf"}, {"nodes", {0}}}}},
      {"nodes", {{{"name", "texture"}, {"mesh", 0}}}},
      {"meshes",
       {{{"name", "texture"},
         {"primitives",
          {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TANGENT", 2}, {"TEXCOORD_0", 3}}},
            {"indices", 4}, {"material", 0}, {"mode", 4}}}}}}},
      {"materials", {materialJson(maps)}},
      {"textures", textures},
      {"images", images},
      {"samplers",
       {{{"magFilter", kLinear}, {"minFilter", kLinearMipmapLinear}, {"wrapS", kClampToEdge},
         {"wrapT", kClampToEdge}}}},
      {"accessors", buffer.accessors},
      {"bufferViews", buffer.views},
      {"buffers",
       {{{"byteLength", buffer.bytes.size()},
         {"uri", "data:application/octet-stream;base64," + base64(buffer.bytes)}}}},
  };
}

std::vector<io::FileSetEntry> texturedGltfFiles(const GltfTextureMaps& maps, double widthM,
                                                double heightM, const std::string& source) {
  const std::array<std::pair<const char*, const Image*>, 6> pngs = {{
      {kBaseColorPng, &maps.baseColor}, {kMetallicRoughnessPng, &maps.metallicRoughness},
      {kAnisotropyPng, &maps.anisotropy}, {kSpecularPng, &maps.specular},
      {kNormalPng, &maps.normal}, {kMaskPng, &maps.mask}}};
  std::vector<io::FileSetEntry> files;
  for (const auto& [file, image] : pngs)
    files.push_back({file, [image](const std::filesystem::path& path) { io::writePng(path, *image); }});
  json document = texturedGltfDocument(maps, widthM, heightM, source);
  files.push_back({kTexturedGltf, [document = std::move(document)](const std::filesystem::path& path) {
                     io::writeStreamReplacing(path, [&](std::ostream& out) { out << document.dump(1) << "\n"; });
                   }});
  return files;
}

}  // namespace slicecap::material_export
