// Reading a fit back: a round trip through lib/fit's JSON, and every way a file can fail to be a
// completed fit refused with the file's name.
#include "slicecap/material_export/material_reader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../support/test_support.hpp"
#include "slicecap/fit/material_json.hpp"

namespace slicecap::material_export {
namespace {

fit::FitResult sheenFit() {
  fit::FitResult r;
  r.material.model = fit::MaterialModel::GgxSheen;
  r.material.diffuseAlbedo = Rgb{0.3, 0.2, 0.1};
  r.material.specularF0 = Rgb{0.04, 0.05, 0.06};
  r.material.specularF90 = 0.7;
  r.material.alphaTangent = 0.35;
  r.material.alphaBitangent = 0.06;
  r.material.tangentDeg = 90.0;
  r.material.sheenColour = Rgb{0.4, 0.1, 0.2};
  r.material.sheenRoughness = 0.3;
  r.metrics.deltaE = 0.4;
  r.choiceReason = "test";
  return r;
}

std::filesystem::path writeDocument(const std::filesystem::path& dir, const nlohmann::ordered_json& d) {
  const auto path = dir / "m.json";
  std::ofstream(path) << d.dump();
  return path;
}

void expectRefused(const std::filesystem::path& path, const std::string& words) {
  try {
    readFittedMaterial(path);
    FAIL() << "accepted " << path;
  } catch (const MaterialFileError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path.string(), 0), 0u) << what;
    EXPECT_NE(what.find(words), std::string::npos) << what;
  }
}

TEST(MaterialReader, RoundTripsLibFitsJson) {
  const auto dir = test::freshTempDir();
  const fit::FitResult r = sheenFit();
  fit::writeMaterialJson(dir / "m.json", fit::materialJson(r, "t.exr"));
  const fit::FittedMaterial m = readFittedMaterial(dir / "m.json");
  EXPECT_EQ(m.model, fit::MaterialModel::GgxSheen);
  EXPECT_DOUBLE_EQ(m.diffuseAlbedo[2], 0.1);
  EXPECT_DOUBLE_EQ(m.specularF0[1], 0.05);
  EXPECT_DOUBLE_EQ(m.specularF90, 0.7);
  EXPECT_DOUBLE_EQ(m.alphaTangent, 0.35);
  EXPECT_DOUBLE_EQ(m.alphaBitangent, 0.06);
  EXPECT_DOUBLE_EQ(m.tangentDeg, 90.0);
  EXPECT_DOUBLE_EQ(m.sheenColour[0], 0.4);
  EXPECT_DOUBLE_EQ(m.sheenRoughness, 0.3);
}

TEST(MaterialReader, RefusesWhatIsNotACompletedFit) {
  const auto dir = test::freshTempDir();
  expectRefused(dir / "absent.json", "cannot be read");
  std::ofstream(dir / "text.json") << "not json {";
  expectRefused(dir / "text.json", "not JSON");

  const nlohmann::ordered_json good = fit::materialJson(sheenFit(), "t.exr");
  auto d = good;
  d["format"] = "something-else";
  expectRefused(writeDocument(dir, d), "not a slicecap material");
  d = good;
  d.erase("metrics");
  expectRefused(writeDocument(dir, d), "not a completed fit");
  d = good;
  d["parameters"].erase("alpha_tangent");
  expectRefused(writeDocument(dir, d), "alpha_tangent");
  d = good;
  d["parameters"]["specular_f0"]["value"][1] = 1.5;
  expectRefused(writeDocument(dir, d), "specular_f0");
  d = good;
  d["parameters"]["alpha_bitangent"]["value"] = -0.1;
  expectRefused(writeDocument(dir, d), "alpha_bitangent");
  d = good;
  d["parameters"]["tangent_deg"]["value"] = "ninety";
  expectRefused(writeDocument(dir, d), "tangent_deg");
  d = good;
  d["model"] = "ward";
  expectRefused(writeDocument(dir, d), "unknown model");
  d = good;
  d["format_version"] = "1";
  expectRefused(writeDocument(dir, d), "format_version \"1\"");
  d = good;
  d["format_version"] = 1.5;  // not version 1, though it truncates to it
  expectRefused(writeDocument(dir, d), "format_version 1.5");
  d = good;
  d["parameters"]["diffuse_albedo"]["value"][0] = 1e300;  // its table overflowed: "dE 0.00"
  expectRefused(writeDocument(dir, d), "diffuse_albedo");
  d = good;
  d["parameters"]["sheen_colour"]["value"][2] = 1e31;
  expectRefused(writeDocument(dir, d), "sheen_colour");
  d = good;
  d["parameters"]["diffuse_albedo"]["value"][0] = 5e6;  // a raw-count table's fit: still read
  EXPECT_DOUBLE_EQ(readFittedMaterial(writeDocument(dir, d)).diffuseAlbedo[0], 5e6);
  d = good;
  d["metrics"]["delta_e"] = -5.0;
  expectRefused(writeDocument(dir, d), "not a completed fit");
}

TEST(MaterialReader, RefusesADirectoryAndDeepNestingByName) {
  const auto dir = test::freshTempDir();
  std::filesystem::create_directory(dir / "folder.json");
  expectRefused(dir / "folder.json", "is a directory");
  // Deep enough that reading it recursively ran out of stack (a crash, not an error).
  const std::size_t depth = 200000;
  std::ofstream(dir / "deep.json") << std::string(depth, '[') << std::string(depth, ']');
  expectRefused(dir / "deep.json", "nested deeper than");
  nlohmann::ordered_json nested = fit::materialJson(sheenFit(), "t.exr");
  nlohmann::json inner = 1;
  for (int level = 0; level < 40; ++level) inner = nlohmann::json::array({inner});
  nested["choice"] = inner;  // a field the reader does not use, nested past the limit
  expectRefused(writeDocument(dir, nested), "nested deeper than");
}

fit::FitResult coatedSheenFit() {
  fit::FitResult r = sheenFit();
  r.material.model = fit::MaterialModel::GgxSheenCoat;
  r.material.coatWeight = 0.85;
  r.material.coatAlpha = 0.04;
  return r;
}

TEST(MaterialReader, RoundTripsACoatAndRefusesABadOne) {
  const auto dir = test::freshTempDir();
  fit::writeMaterialJson(dir / "m.json", fit::materialJson(coatedSheenFit(), "t.exr"));
  const fit::FittedMaterial m = readFittedMaterial(dir / "m.json");
  EXPECT_EQ(m.model, fit::MaterialModel::GgxSheenCoat);
  EXPECT_DOUBLE_EQ(m.coatWeight, 0.85);
  EXPECT_DOUBLE_EQ(m.coatAlpha, 0.04);
  EXPECT_DOUBLE_EQ(m.sheenRoughness, 0.3);

  const nlohmann::ordered_json good = fit::materialJson(coatedSheenFit(), "t.exr");
  auto d = good;
  d["parameters"].erase("coat_alpha");
  expectRefused(writeDocument(dir, d), "coat_alpha");
  d = good;
  d["parameters"]["coat_weight"]["value"] = 1.2;
  expectRefused(writeDocument(dir, d), "coat_weight");
  // A coat's parameters under a model without one are not read: the model says the terms.
  d = good;
  d["model"] = "ggx+sheen";
  EXPECT_EQ(readFittedMaterial(writeDocument(dir, d)).model, fit::MaterialModel::GgxSheen);
}

}  // namespace
}  // namespace slicecap::material_export

namespace slicecap::material_export {
namespace {

// Format version 2 says the sheen's form; version 1 (before "sheen_form") holds the additive
// sheen and is still read and evaluated in it, so an old file's table does not change.
TEST(MaterialReader, ReadsTheSheenFormOfVersionTwoAndVersionOnesAdditiveSheen) {
  const auto dir = test::freshTempDir();
  nlohmann::ordered_json d = fit::materialJson(sheenFit(), "t.exr");
  ASSERT_EQ(d["format_version"], 2);
  ASSERT_EQ(d["sheen_form"], "khr_materials_sheen");
  EXPECT_EQ(readFittedMaterial(writeDocument(dir, d)).sheenForm, fit::SheenForm::Khr);
  d["sheen_form"] = "additive";
  EXPECT_EQ(readFittedMaterial(writeDocument(dir, d)).sheenForm, fit::SheenForm::Additive);

  nlohmann::ordered_json v1 = fit::materialJson(sheenFit(), "t.exr");
  v1["format_version"] = 1;
  v1.erase("sheen_form");
  const fit::FittedMaterial old = readFittedMaterial(writeDocument(dir, v1));
  EXPECT_EQ(old.sheenForm, fit::SheenForm::Additive);
  // Evaluated in its own form: the sheen added on top, the base not dimmed.
  fit::FittedMaterial khr = old;
  khr.sheenForm = fit::SheenForm::Khr;
  const UnitVector l{0.0, 0.0, 1.0}, v{0.8, 0.0, 0.6};
  EXPECT_GT(std::abs(old.evaluate(l, v)[0] - khr.evaluate(l, v)[0]), 1e-3);
  // A version-1 sheen may be brighter than 1 (it was not bounded); the khr form's may not.
  v1["parameters"]["sheen_colour"]["value"][0] = 1.5;
  EXPECT_DOUBLE_EQ(readFittedMaterial(writeDocument(dir, v1)).sheenColour[0], 1.5);
  d["sheen_form"] = "khr_materials_sheen";
  d["parameters"]["sheen_colour"]["value"][0] = 1.5;
  expectRefused(writeDocument(dir, d), "sheen_colour");
}

TEST(MaterialReader, RefusesAVersionTwoFileThatDoesNotSayItsSheenForm) {
  const auto dir = test::freshTempDir();
  nlohmann::ordered_json d = fit::materialJson(sheenFit(), "t.exr");
  d.erase("sheen_form");
  expectRefused(writeDocument(dir, d), "\"sheen_form\" is missing");
  d["sheen_form"] = "charlie";
  expectRefused(writeDocument(dir, d), "\"sheen_form\" is \"charlie\"");
  d["format_version"] = 3;
  expectRefused(writeDocument(dir, d), "format_version 3");
}

}  // namespace
}  // namespace slicecap::material_export
