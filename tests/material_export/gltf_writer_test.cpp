// The glTF container: base64, the document's structure and extensions, the GLB layout, the file.
#include "slicecap/material_export/gltf_writer.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "../support/test_support.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::material_export {
namespace {

fit::FittedMaterial velvet() {
  fit::FittedMaterial m;
  m.model = fit::MaterialModel::GgxSheen;
  m.diffuseAlbedo = Rgb{0.3, 0.05, 0.05};
  m.specularF0 = Rgb::gray(0.04);
  m.specularF90 = 1.0;
  m.alphaTangent = 0.5;
  m.alphaBitangent = 0.2;
  m.tangentDeg = 45.0;
  m.sheenColour = Rgb{0.6, 0.1, 0.1};
  m.sheenRoughness = 0.3;
  return m;
}

std::uint32_t le32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return b[at] | b[at + 1] << 8 | b[at + 2] << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}

TEST(GltfWriter, Base64MatchesRfc4648Vectors) {
  const auto bytes = [](const std::string& s) { return std::vector<std::uint8_t>(s.begin(), s.end()); };
  EXPECT_EQ(base64(bytes("")), "");
  EXPECT_EQ(base64(bytes("f")), "Zg==");
  EXPECT_EQ(base64(bytes("fo")), "Zm8=");
  EXPECT_EQ(base64(bytes("foo")), "Zm9v");
  EXPECT_EQ(base64(bytes("foobar")), "Zm9vYmFy");
  EXPECT_EQ(base64({0xff, 0xfe, 0x00}), "//4A");
}

TEST(GltfWriter, DocumentHasTheMaterialExtensionsAndConsistentBuffers) {
  const GltfAsset asset = gltfAsset(velvet(), "velvet.json");
  const auto& d = asset.document;
  std::vector<std::string> used = d["extensionsUsed"];
  for (const char* e : {"KHR_materials_anisotropy", "KHR_materials_specular", "KHR_materials_ior",
                        "KHR_materials_sheen"})
    EXPECT_NE(std::find(used.begin(), used.end(), e), used.end()) << e;
  const auto& ext = d["materials"][0]["extensions"];
  EXPECT_NEAR(ext["KHR_materials_anisotropy"]["anisotropyRotation"].get<double>(), 0.785398, 1e-5);
  EXPECT_NEAR(ext["KHR_materials_sheen"]["sheenRoughnessFactor"].get<double>(), std::sqrt(0.3), 1e-12);
  EXPECT_EQ(d["buffers"][0]["byteLength"].get<std::size_t>(), asset.buffer.size());
  for (const auto& view : d["bufferViews"]) {
    EXPECT_EQ(view["byteOffset"].get<std::size_t>() % 4, 0u);
    EXPECT_LE(view["byteOffset"].get<std::size_t>() + view["byteLength"].get<std::size_t>(),
              asset.buffer.size());
  }
  for (const auto& mesh : d["meshes"]) {
    const auto& attributes = mesh["primitives"][0]["attributes"];
    for (const char* a : {"POSITION", "NORMAL", "TANGENT", "TEXCOORD_0"}) EXPECT_TRUE(attributes.contains(a)) << a;
    EXPECT_TRUE(d["accessors"][attributes["POSITION"].get<int>()].contains("min"));
  }
  // The losses travel with the file, for whoever opens it later.
  EXPECT_FALSE(d["asset"]["extras"]["slicecap_conversion_losses"].empty());
  EXPECT_FALSE(asset.report.losses.empty());
}

TEST(GltfWriter, ACoatIsKhrMaterialsClearcoat) {
  fit::FittedMaterial m = velvet();
  EXPECT_FALSE(gltfAsset(m, "v.json").document["materials"][0]["extensions"].contains(
      "KHR_materials_clearcoat"));
  m.model = fit::MaterialModel::GgxSheenCoat;
  m.coatWeight = 0.9;
  m.coatAlpha = 0.04;
  const auto& d = gltfAsset(m, "coated.json").document;
  std::vector<std::string> used = d["extensionsUsed"];
  EXPECT_NE(std::find(used.begin(), used.end(), "KHR_materials_clearcoat"), used.end());
  const auto& coat = d["materials"][0]["extensions"]["KHR_materials_clearcoat"];
  EXPECT_DOUBLE_EQ(coat["clearcoatFactor"].get<double>(), 0.9);
  EXPECT_NEAR(coat["clearcoatRoughnessFactor"].get<double>(), 0.2, 1e-12);
}

TEST(GltfWriter, TextEmbedsTheBufferAsADataUri) {
  const GltfAsset asset = gltfAsset(velvet(), "velvet.json");
  const auto d = nlohmann::json::parse(gltfText(asset));
  const std::string uri = d["buffers"][0]["uri"];
  const std::string prefix = "data:application/octet-stream;base64,";
  ASSERT_EQ(uri.rfind(prefix, 0), 0u);
  EXPECT_EQ(uri.size() - prefix.size(), (asset.buffer.size() + 2) / 3 * 4);
}

TEST(GltfWriter, GlbHasTheBinaryLayout) {
  const GltfAsset asset = gltfAsset(velvet(), "velvet.json");
  const std::vector<std::uint8_t> glb = glbBytes(asset);
  ASSERT_GE(glb.size(), 28u);
  EXPECT_EQ(le32(glb, 0), 0x46546C67u);
  EXPECT_EQ(le32(glb, 4), 2u);
  EXPECT_EQ(le32(glb, 8), glb.size());
  const std::uint32_t jsonLength = le32(glb, 12);
  EXPECT_EQ(jsonLength % 4, 0u);
  EXPECT_EQ(le32(glb, 16), 0x4E4F534Au);
  const std::size_t bin = 20 + jsonLength;
  EXPECT_EQ(le32(glb, bin + 4), 0x004E4942u);
  EXPECT_EQ(le32(glb, bin), glb.size() - bin - 8);
  EXPECT_GE(le32(glb, bin), asset.buffer.size());
  const auto d = nlohmann::json::parse(std::string(glb.begin() + 20, glb.begin() + 20 + jsonLength));
  EXPECT_FALSE(d["buffers"][0].contains("uri"));  // the GLB's own BIN chunk
}

TEST(GltfWriter, WritesGlbOrTextByExtension) {
  const auto dir = test::freshTempDir();
  writeGltf(dir / "m.GLB", velvet(), "velvet.json");
  writeGltf(dir / "m.gltf", velvet(), "velvet.json");
  std::ifstream glb(dir / "m.GLB", std::ios::binary), text(dir / "m.gltf");
  std::string magic(4, '\0');
  glb.read(magic.data(), 4);
  EXPECT_EQ(magic, "glTF");
  EXPECT_EQ(nlohmann::json::parse(text)["asset"]["version"], "2.0");
}

TEST(GltfWriter, UnwritablePathThrowsNamingIt) {
  const auto dir = test::freshTempDir();
  try {
    writeGltf(dir / "missing" / "m.gltf", velvet(), "velvet.json");
    FAIL() << "no exception";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("m.gltf"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slicecap::material_export
