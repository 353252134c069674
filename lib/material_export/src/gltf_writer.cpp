// Lays the preview meshes into one buffer with accessors and writes the material with its extensions
// (glTF 2.0 specification, "Meshes", "Binary glTF Layout"; KHR_materials_* READMEs).
#include "slicecap/material_export/gltf_writer.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <limits>
#include <ostream>

#include "gltf_buffer.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/material_export/gltf_brdf.hpp"
#include "slicecap/material_export/gltf_form.hpp"
#include "slicecap/material_export/gltf_material.hpp"
#include "slicecap/material_export/preview_mesh.hpp"

namespace slicecap::material_export {
namespace {

using json = nlohmann::ordered_json;

using namespace gltf_buffer;

json rgbJson(const Rgb& c) { return {c[0], c[1], c[2]}; }

json lossesJson(const ExportReport& report) {
  json losses = json::array();
  for (const ConversionLoss& loss : report.losses)
    losses.push_back({{"kind", toString(loss.kind)}, {"detail", loss.detail}});
  return losses;
}

json measuredJson(const ExportReport& report) {
  if (!report.measured) return nullptr;
  return {{"delta_e", report.measured->deltaE},
          {"rmse", report.measured->rmse},
          {"psnr_db", report.measured->psnrDb},
          {"convention", "glTF's BRDF of these factors tabulated on the Bonn grid against the fitted "
                         "material's table, as slicecap compare FIT GLTF"}};
}

void appendLittleEndian32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

}  // namespace

nlohmann::ordered_json gltfMaterialJson(const GltfMaterial& g) {
  json extensions = json::object();
  extensions["KHR_materials_anisotropy"] = {{"anisotropyStrength", g.anisotropyStrength},
                                            {"anisotropyRotation", g.anisotropyRotationRad}};
  extensions["KHR_materials_specular"] = {{"specularFactor", g.specularFactor},
                                          {"specularColorFactor", rgbJson(g.specularColorFactor)}};
  extensions["KHR_materials_ior"] = {{"ior", g.ior}};
  if (g.hasSheen)
    extensions["KHR_materials_sheen"] = {{"sheenColorFactor", rgbJson(g.sheenColorFactor)},
                                         {"sheenRoughnessFactor", g.sheenRoughnessFactor}};
  if (g.hasClearcoat)
    extensions["KHR_materials_clearcoat"] = {
        {"clearcoatFactor", g.clearcoatFactor},
        {"clearcoatRoughnessFactor", g.clearcoatRoughnessFactor}};
  return {{"name", "slicecap-fit"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {g.baseColorFactor[0], g.baseColorFactor[1], g.baseColorFactor[2], 1.0}},
            {"metallicFactor", g.metallicFactor},
            {"roughnessFactor", g.roughnessFactor}}},
          {"extensions", extensions}};
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t chunk = static_cast<std::uint32_t>(bytes[i]) << 16;
    if (n > 1) chunk |= static_cast<std::uint32_t>(bytes[i + 1]) << 8;
    if (n > 2) chunk |= bytes[i + 2];
    out.push_back(kAlphabet[(chunk >> 18) & 63]);
    out.push_back(kAlphabet[(chunk >> 12) & 63]);
    out.push_back(n > 1 ? kAlphabet[(chunk >> 6) & 63] : '=');
    out.push_back(n > 2 ? kAlphabet[chunk & 63] : '=');
  }
  return out;
}

GltfAsset gltfAsset(const fit::FittedMaterial& material, const std::string& source) {
  const GltfConversion conversion = chooseGltfForm(material);
  GltfAsset asset;
  asset.report = {"glTF 2.0", conversion.losses, std::nullopt};
  // A material that reflects nothing has no table to compare against: nothing to measure.
  if (gltfVersusFitExists(material)) asset.report.measured = gltfVersusFit(material);

  BufferBuilder buffer;
  json meshes = json::array(), nodes = json::array();
  const std::vector<std::pair<PreviewMesh, double>> placed = {{uvSphere(0.5, 64, 32), -0.7},
                                                              {cylinder(0.4, 1.0, 64), 0.7}};
  for (const auto& [mesh, x] : placed) {
    json attributes = {{"POSITION", buffer.addVectors(mesh.positions, kFloat, "VEC3", true)},
                       {"NORMAL", buffer.addVectors(mesh.normals, kFloat, "VEC3", false)},
                       {"TANGENT", buffer.addVectors(mesh.tangents, kFloat, "VEC4", false)},
                       {"TEXCOORD_0", buffer.addVectors(mesh.uvs, kFloat, "VEC2", false)}};
    const int indices = buffer.addIndices(mesh.indices);
    meshes.push_back({{"name", mesh.name},
                      {"primitives", {{{"attributes", attributes}, {"indices", indices},
                                       {"material", 0}, {"mode", 4}}}}});
    nodes.push_back({{"name", mesh.name},
                     {"mesh", static_cast<int>(meshes.size()) - 1},
                     {"translation", {x, 0.0, 0.0}}});
  }

  json materialEntry = gltfMaterialJson(conversion.material);
  json extensionsUsed = json::array();
  for (const auto& [name, value] : materialEntry["extensions"].items()) extensionsUsed.push_back(name);
  asset.document = {
      {"asset",
       {{"version", "2.0"},
        {"generator", std::string("slicecap ") + kVersion},
        {"extras",
         {{"slicecap_source", source},
          {"slicecap_conventions",
           "material fitted by slicecap fit (docs/material-fit.md), mapped as docs/material-export.md; "
           "TANGENT is the table's azimuth-0 axis, anisotropyRotation the fitted tangent_deg"},
          {"slicecap_conversion_losses", lossesJson(asset.report)},
          {"slicecap_gltf_versus_fit", measuredJson(asset.report)}}}}},
      {"extensionsUsed", extensionsUsed},
      {"scene", 0},
      {"scenes", {{{"name", "slicecap preview"}, {"nodes", {0, 1}}}}},
      {"nodes", nodes},
      {"meshes", meshes},
      {"materials", {materialEntry}},
      {"accessors", buffer.accessors},
      {"bufferViews", buffer.views},
      {"buffers", {{{"byteLength", buffer.bytes.size()}}}},
  };
  asset.buffer = std::move(buffer.bytes);
  return asset;
}

std::string gltfText(const GltfAsset& asset) {
  json document = asset.document;
  document["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(asset.buffer);
  return document.dump(1) + "\n";
}

std::vector<std::uint8_t> glbBytes(const GltfAsset& asset) {
  // glTF 2.0, "Binary glTF Layout": 12-byte header, then chunks whose lengths are multiples of 4;
  // the JSON chunk is padded with spaces, the BIN chunk with zeros.
  std::string text = asset.document.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  std::vector<std::uint8_t> bin = asset.buffer;
  while (bin.size() % 4 != 0) bin.push_back(0);
  std::vector<std::uint8_t> out;
  const auto total = static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size());
  appendLittleEndian32(out, 0x46546C67u);  // "glTF"
  appendLittleEndian32(out, 2u);
  appendLittleEndian32(out, total);
  appendLittleEndian32(out, static_cast<std::uint32_t>(text.size()));
  appendLittleEndian32(out, 0x4E4F534Au);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  appendLittleEndian32(out, static_cast<std::uint32_t>(bin.size()));
  appendLittleEndian32(out, 0x004E4942u);  // "BIN\0"
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

std::string gltfFileContents(const GltfAsset& asset, const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".glb") return gltfText(asset);
  const std::vector<std::uint8_t> bytes = glbBytes(asset);
  return {bytes.begin(), bytes.end()};
}

ExportReport writeGltf(const std::filesystem::path& path, const fit::FittedMaterial& material,
                       const std::string& source) {
  const GltfAsset asset = gltfAsset(material, source);
  const std::string contents = gltfFileContents(asset, path);
  io::writeStreamReplacing(path, [&](std::ostream& out) { out << contents; });
  return asset.report;
}

}  // namespace slicecap::material_export
