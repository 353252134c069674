// `slicecap fit ... --gltf/--mtlx/--mitsuba` and `slicecap fit MATERIAL.json --gltf ...`: files
// written, losses printed, and a material that is not a completed fit refused, naming it.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::cli {
namespace {

TEST(MaterialExports, FitWritesEveryExportAndPrintsTheLosses) {
  const auto dir = test::freshTempDir();
  io::writeAbrdfExr(dir / "steel.exr", models::tabulate(*models::findMaterial("brushed-steel-30")));
  const auto result = test::runSlicecap(
      {"fit", (dir / "steel.exr").string(), "-o", (dir / "steel.json").string(), "--gltf",
       (dir / "steel.glb").string(), "--mtlx", (dir / "steel.mtlx").string(), "--mitsuba",
       (dir / "steel.xml").string()});
  ASSERT_EQ(result.code, 0) << result.err;
  for (const char* f : {"steel.json", "steel.glb", "steel.mtlx", "steel.xml"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  EXPECT_NE(result.out.find("wrote " + (dir / "steel.glb").string() + " (glTF 2.0)"),
            std::string::npos) << result.out;
  EXPECT_NE(result.out.find("tangent-from-mesh"), std::string::npos) << result.out;
}

TEST(MaterialExports, AnEarlierFitIsExportedWithoutFittingAgain) {
  const auto dir = test::freshTempDir();
  io::writeAbrdfExr(dir / "steel.exr", models::tabulate(*models::findMaterial("brushed-steel-30")));
  ASSERT_EQ(test::runSlicecap({"fit", (dir / "steel.exr").string(), "-o", (dir / "m.json").string()}).code, 0);
  const auto result =
      test::runSlicecap({"fit", (dir / "m.json").string(), "--gltf", (dir / "m.gltf").string()});
  ASSERT_EQ(result.code, 0) << result.err;
  EXPECT_EQ(result.out.find("fitted"), std::string::npos) << result.out;
  std::ifstream in(dir / "m.gltf");
  const auto d = nlohmann::json::parse(in);
  // brushed-steel-30: ax 0.1 along 30 deg, ay 0.4 across: the larger alpha lies at 120 deg.
  EXPECT_NEAR(d["materials"][0]["extensions"]["KHR_materials_anisotropy"]["anisotropyRotation"]
                  .get<double>(), 120.0 * 3.14159265358979 / 180.0, 1e-3);
}

TEST(MaterialExports, AMaterialThatWasNotFittedIsRefusedNamingIt) {
  const auto dir = test::freshTempDir();
  std::ofstream(dir / "broken.json") << "{\"format\": \"slicecap-material\", \"format_version\": 1}";
  const auto result =
      test::runSlicecap({"fit", (dir / "broken.json").string(), "--gltf", (dir / "m.gltf").string()});
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.err.find("broken.json"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "m.gltf"));
}

TEST(MaterialExports, UsageErrors) {
  // Nothing to export; fit options on an existing material; an export over the input.
  EXPECT_EQ(test::runSlicecap({"fit", "m.json"}).code, 2);
  EXPECT_EQ(test::runSlicecap({"fit", "m.json", "--gltf", "a.gltf", "--no-sheen"}).code, 2);
  const auto dir = test::freshTempDir();
  std::ofstream(dir / "m.json") << "{}";
  EXPECT_EQ(test::runSlicecap({"fit", (dir / "m.json").string(), "--mtlx", (dir / "m.json").string()}).code, 2);
  EXPECT_EQ(test::runSlicecap({"fit", "t.exr", "-o", "same.gltf", "--gltf", "same.gltf"}).code, 2);
}

}  // namespace
}  // namespace slicecap::cli
