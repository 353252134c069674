// `slicecap fit BTF_DIR -o MAPS_DIR` from the command line: a small BTF of known GGX texels in,
// glTF texture maps, the mask and a textured glTF out; a texel with no samples named and masked;
// an output that would land in (or over) the BTF refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>

#include "../support/cli_runner.hpp"
#include "../support/file_size_limit.hpp"
#include "../support/test_support.hpp"
#include "../support/tilted_table.hpp"
#include "slicecap/btf/btf_files.hpp"
#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/io/png_image.hpp"

namespace slicecap::fit {
namespace {

// A 2 x 2 BTF: three brushed texels (tangent 30 deg), texel (0,1) tilted 15 deg toward azimuth
// 60 deg, and texel (1,1) with no samples.
test::tilt::Vec tiltedNormal() {
  return test::tilt::tiltedNormal(15.0, 60.0);
}

class TextureFitCommand : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    // freshTempDir() needs a running test; one directory for the suite instead, of this process:
    // ctest runs each test of the suite in a process of its own, in parallel, and one folder
    // shared by them was emptied under the others' feet.
    directory_ = new std::filesystem::path(std::filesystem::path(SLICECAP_TEST_TMP_DIR) /
                                           ("TextureFitCommand-" + std::to_string(::getpid())));
    std::filesystem::remove_all(*directory_);
    std::filesystem::create_directories(*directory_);
    btf::BtfTexture texture(2);
    for (std::size_t texel = 0; texel < 3; ++texel) {
      FittedMaterial m;
      m.diffuseAlbedo = {0.3, 0.2, 0.1 + 0.1 * double(texel)};
      m.specularF0 = Rgb::gray(0.08);
      m.alphaTangent = 0.3;
      m.alphaBitangent = 0.1;
      m.tangentDeg = 30.0;
      texture.setTexel(texel,
                       texel == 2 ? test::tilt::tabulateTilted(m, tiltedNormal()) : tabulate(m));
    }
    btf::BtfDescription description;
    description.windowMm = {-10.0, -10.0, 10.0, 10.0};
    btf::writeBtfDirectory(btf(), texture, tabulate(FittedMaterial{}), description, {}, 2);
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    std::filesystem::remove_all(*directory_, ignored);
    delete directory_;
  }
  static std::filesystem::path btf() { return *directory_ / "btf"; }
  static std::filesystem::path root() { return *directory_; }

 private:
  static inline std::filesystem::path* directory_ = nullptr;
};

TEST_F(TextureFitCommand, WritesTheMapsAndNamesTheTexelWithNoSamples) {
  const auto maps = root() / "maps";
  const auto result =
      test::runSlicecap({"fit", btf().string(), "-o", maps.string(), "--threads", "2"});
  ASSERT_EQ(result.code, 0) << result.err;
  EXPECT_NE(result.err.find("texel (1,1): no samples"), std::string::npos) << result.err;
  EXPECT_NE(result.out.find("fitted 3 of 4 texels"), std::string::npos) << result.out;

  const Image mask = io::readPng(maps / "mask.png");
  EXPECT_EQ(mask.at(0, 0, 0), 255);
  EXPECT_EQ(mask.at(1, 0, 0), 255);
  EXPECT_EQ(mask.at(1, 1, 0), 0);
  // KHR_materials_anisotropy: RG the direction in [-1, 1] as [0, 1], B the strength;
  // alpha_t = mix(alpha_b, 1, strength^2) = 0.3 with alpha_b 0.1.
  const Image anisotropy = io::readPng(maps / "anisotropy.png");
  const double angleDeg = std::atan2(anisotropy.at(0, 0, 1) / 127.5 - 1.0,
                                     anisotropy.at(0, 0, 0) / 127.5 - 1.0) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(angleDeg, 30.0, 1.0);
  EXPECT_NEAR(anisotropy.at(0, 0, 2) / 255.0, std::sqrt(0.2 / 0.9), 2.0 / 255);
  const Image roughness = io::readPng(maps / "metallic_roughness.png");
  EXPECT_NEAR(roughness.at(1, 0, 1) / 255.0, std::sqrt(0.1), 2.0 / 255);
  EXPECT_EQ(roughness.at(1, 0, 2), 0);  // metallic

  // glTF's normalTexture: RGB = (n + 1) / 2, x along TANGENT (+x), y along the bitangent (+y).
  const Image normal = io::readPng(maps / "normal.png");
  const test::tilt::Vec n = tiltedNormal();
  EXPECT_NEAR(normal.at(0, 1, 0), 127.5 * (n.x + 1.0), 2.0);
  EXPECT_NEAR(normal.at(0, 1, 1), 127.5 * (n.y + 1.0), 2.0);
  EXPECT_NEAR(normal.at(0, 1, 2), 127.5 * (n.z + 1.0), 2.0);
  for (const auto& [x, y] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}}) {
    EXPECT_NEAR(normal.at(x, y, 0), 128, 1) << x << "," << y;
    EXPECT_NEAR(normal.at(x, y, 1), 128, 1) << x << "," << y;
    EXPECT_EQ(normal.at(x, y, 2), 255) << x << "," << y;
  }

  std::ifstream mapsJson(maps / "maps.json");
  const auto summary = nlohmann::json::parse(mapsJson);
  ASSERT_EQ(summary["failed_texels"].size(), 1u);
  EXPECT_EQ(summary["failed_texels"][0]["x"], 1);
  EXPECT_EQ(summary["failed_texels"][0]["status"], "no samples");
  EXPECT_EQ(summary["texels_tilt_fitted"], 3);
  EXPECT_EQ(summary["flat_normal_texels"].size(), 0u);
  EXPECT_TRUE(summary["normal_map"].get<std::string>().starts_with("fitted"))
      << summary["normal_map"];
  std::ifstream gltfFile(maps / "material.gltf");
  const auto gltf = nlohmann::json::parse(gltfFile);
  EXPECT_EQ(gltf["images"].size(), 5u);
  for (const auto& image : gltf["images"])
    EXPECT_TRUE(std::filesystem::exists(maps / image["uri"].get<std::string>())) << image;
  EXPECT_TRUE(gltf["meshes"][0]["primitives"][0]["attributes"].contains("TANGENT"));
  EXPECT_EQ(gltf["materials"][0]["extensions"]["KHR_materials_anisotropy"]["anisotropyTexture"]["index"], 2);
  EXPECT_EQ(gltf["images"][gltf["materials"][0]["normalTexture"]["index"].get<int>()]["uri"],
            "normal.png");
}

TEST_F(TextureFitCommand, RefusesAnOutputInOrOverTheBtf) {
  for (const auto& output : {btf(), btf() / "maps", root()}) {
    const auto result = test::runSlicecap({"fit", btf().string(), "-o", output.string()});
    EXPECT_EQ(result.code, 2) << output;
    EXPECT_NE(result.err.find("-o " + output.string()), std::string::npos) << result.err;
  }
  EXPECT_FALSE(std::filesystem::exists(btf() / "maps"));
  EXPECT_FALSE(std::filesystem::exists(btf() / "material.gltf"));
}

TEST_F(TextureFitCommand, RefusesTableExportOptionsAndATextureStore) {
  const auto withGltf = test::runSlicecap(
      {"fit", btf().string(), "-o", (root() / "m2").string(), "--gltf", (root() / "x.gltf").string()});
  EXPECT_EQ(withGltf.code, 2) << withGltf.err;
  const auto store = root() / "store";
  std::filesystem::create_directories(store);
  std::ofstream(store / "texture.json") << "{}";
  const auto fromStore = test::runSlicecap({"fit", store.string(), "-o", (root() / "m3").string()});
  EXPECT_EQ(fromStore.code, 1);
  EXPECT_NE(fromStore.err.find("slicecap btf"), std::string::npos) << fromStore.err;
}

// The maps, material.gltf and maps.json are one set: a write that fails part-way (a full disk) used
// to leave new maps beside the previous maps.json and material.gltf.
TEST_F(TextureFitCommand, AFailedWriteLeavesThePreviousMapsWhole) {
  const auto maps = root() / "maps-kept";
  ASSERT_EQ(test::runSlicecap({"fit", btf().string(), "-o", maps.string(), "--threads", "1"}).code, 0);
  // Marked, so that a file the next run replaced would show.
  for (const char* name : {"base_color.png", "maps.json", "material.gltf"})
    std::ofstream(maps / name) << "previous " << name;
  {
    const test::FileSizeLimit limit(600);  // the PNGs fit, material.gltf does not: a full disk
    const auto result =
        test::runSlicecap({"fit", btf().string(), "-o", maps.string(), "--threads", "1"});
    EXPECT_EQ(result.code, 1);
    EXPECT_NE(result.err.find("material.gltf"), std::string::npos) << result.err;
  }
  for (const char* name : {"base_color.png", "maps.json", "material.gltf"}) {
    std::ifstream in(maps / name);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), std::string("previous ") + name);
  }
  for (const auto& entry : std::filesystem::directory_iterator(maps))
    EXPECT_FALSE(entry.path().filename().string().starts_with(".")) << entry.path();
}

TEST_F(TextureFitCommand, RefusesTableOptionsAndAFileForTheMapsDirectory) {
  const auto noSheen = test::runSlicecap(
      {"fit", btf().string(), "-o", (root() / "m4").string(), "--no-sheen"});
  EXPECT_EQ(noSheen.code, 2) << noSheen.err;
  EXPECT_NE(noSheen.err.find("--no-sheen"), std::string::npos) << noSheen.err;
  const auto file = root() / "a-file";
  std::ofstream(file) << "kept";
  const auto onFile = test::runSlicecap({"fit", btf().string(), "-o", file.string()});
  EXPECT_EQ(onFile.code, 1) << onFile.err;
  EXPECT_NE(onFile.err.find(file.string() + ": not a directory"), std::string::npos) << onFile.err;
  std::ifstream in(file);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "kept");
}

}  // namespace
}  // namespace slicecap::fit
