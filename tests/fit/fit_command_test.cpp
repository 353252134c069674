// `slicecap fit` from the command line: a table in, a material JSON out; bad input named, and
// nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "../support/cli_runner.hpp"
#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "../support/test_support.hpp"

namespace slicecap::fit {
namespace {

TEST(FitCommand, WritesTheFittedMaterial) {
  const auto dir = test::freshTempDir();
  io::writeAbrdfExr(dir / "copper.exr",
                    models::tabulate(*models::findMaterial("copper-ggx-15")));
  const auto result = test::runSlicecap(
      {"fit", (dir / "copper.exr").string(), "-o", (dir / "copper.json").string()});
  ASSERT_EQ(result.code, 0) << result.err;
  EXPECT_NE(result.out.find("fitted ggx"), std::string::npos) << result.out;
  std::ifstream in(dir / "copper.json");
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["model"], "ggx");
  EXPECT_NEAR(doc["parameters"]["alpha_tangent"]["value"].get<double>(), 0.30, 0.003);
  EXPECT_NEAR(doc["parameters"]["tangent_deg"]["value"].get<double>(), 15.0, 0.1);
  EXPECT_LE(doc["metrics"]["delta_e"].get<double>(), 1.0);
}

TEST(FitCommand, AllZeroTableFailsNamingItAndWritesNothing) {
  const auto dir = test::freshTempDir();
  io::writeF32Table(dir / "black.f32", Abrdf{});
  const auto result =
      test::runSlicecap({"fit", (dir / "black.f32").string(), "-o", (dir / "m.json").string()});
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.err.find("black.f32"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "m.json"));
}

TEST(FitCommand, NonConvergenceFailsAndKeepsAnOldMaterial) {
  const auto dir = test::freshTempDir();
  io::writeAbrdfExr(dir / "satin.exr", models::tabulate(*models::findMaterial("satin-blue-45")));
  std::ofstream(dir / "m.json") << "{\"old\": true}";
  const auto result = test::runSlicecap({"fit", (dir / "satin.exr").string(), "-o",
                                         (dir / "m.json").string(), "--max-iterations", "2"});
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.err.find("satin.exr"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("did not converge"), std::string::npos) << result.err;
  std::ifstream in(dir / "m.json");
  EXPECT_EQ(nlohmann::json::parse(in)["old"], true);
}

TEST(FitCommand, ACoatedTableGetsACoatUnlessTold) {
  const auto dir = test::freshTempDir();
  FittedMaterial lacquer;
  lacquer.model = MaterialModel::GgxCoat;
  lacquer.diffuseAlbedo = {0.1, 0.2, 0.4};
  lacquer.specularF0 = Rgb::gray(0.04);
  lacquer.alphaTangent = lacquer.alphaBitangent = 0.4;
  lacquer.coatWeight = 1.0;
  lacquer.coatAlpha = 0.08;
  io::writeF32Table(dir / "lacquer.f32", tabulate(lacquer));
  const auto coated = test::runSlicecap(
      {"fit", (dir / "lacquer.f32").string(), "-o", (dir / "coated.json").string()});
  ASSERT_EQ(coated.code, 0) << coated.err;
  EXPECT_NE(coated.out.find("fitted ggx+coat"), std::string::npos) << coated.out;
  const auto plain = test::runSlicecap({"fit", (dir / "lacquer.f32").string(), "-o",
                                        (dir / "plain.json").string(), "--no-coat"});
  ASSERT_EQ(plain.code, 0) << plain.err;
  std::ifstream in(dir / "plain.json");
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["model"].get<std::string>().find("coat"), std::string::npos);
  EXPECT_NE(doc["choice"].get<std::string>().find("coat not tried"), std::string::npos);
  // --no-coat is for a fit, not for exporting one already made.
  const auto misuse = test::runSlicecap(
      {"fit", (dir / "coated.json").string(), "--no-coat", "--gltf", (dir / "c.glb").string()});
  EXPECT_EQ(misuse.code, 2);
}

// The material and its exports replace their files as one: an export that cannot be written (its
// folder missing, a full disk) costs neither an earlier fit at -o nor an earlier export.
TEST(FitCommand, AnExportThatCannotBeWrittenKeepsEveryEarlierOutput) {
  const auto dir = test::freshTempDir();
  io::writeAbrdfExr(dir / "copper.exr", models::tabulate(*models::findMaterial("copper-ggx-15")));
  std::ofstream(dir / "m.json") << "{\"old\": true}";
  std::ofstream(dir / "m.mtlx") << "old mtlx";
  const std::vector<std::string> unwritables{(dir / "missing" / "m.gltf").string(), "/dev/full"};
  for (const std::string& unwritable : unwritables) {
    const auto result = test::runSlicecap({"fit", (dir / "copper.exr").string(), "-o",
                                           (dir / "m.json").string(), "--mtlx",
                                           (dir / "m.mtlx").string(), "--gltf", unwritable});
    EXPECT_EQ(result.code, 1) << unwritable;
    EXPECT_NE(result.err.find(unwritable), std::string::npos) << result.err;
    std::ifstream json(dir / "m.json");
    EXPECT_EQ(nlohmann::json::parse(json)["old"], true) << unwritable;
    std::ifstream mtlx(dir / "m.mtlx");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(mtlx), {}), "old mtlx") << unwritable;
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"copper.exr", "m.json", "m.mtlx"})) << unwritable;
  }
}

TEST(FitCommand, BadIterationCountIsAUsageError) {
  const auto result = test::runSlicecap({"fit", "t.exr", "-o", "m.json", "--max-iterations", "0"});
  EXPECT_EQ(result.code, 2);
}

}  // namespace
}  // namespace slicecap::fit
