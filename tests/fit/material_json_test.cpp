// The JSON of a fit: the model, every parameter with its unit, the conventions, the metrics; and
// the file written whole or not at all.
#include "slicecap/fit/material_json.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "slicecap/io/io_error.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "../support/test_support.hpp"

namespace slicecap::fit {
namespace {

FitResult steelFit() {
  FitOptions options;
  options.trySheen = false;
  return fitMaterial(models::tabulate(*models::findMaterial("brushed-steel-30")), "steel.exr",
                     options);
}

TEST(MaterialJson, SaysTheModelParametersUnitsConventionsAndMetrics) {
  const FitResult r = steelFit();
  const auto doc = materialJson(r, "tables/steel.exr");
  EXPECT_EQ(doc["format"], kMaterialFormat);
  EXPECT_EQ(doc["format_version"], kMaterialFormatVersion);
  EXPECT_EQ(doc["source"], "tables/steel.exr");
  EXPECT_EQ(doc["model"], "ggx");
  EXPECT_EQ(doc["choice"], r.choiceReason);
  for (const char* name :
       {"diffuse_albedo", "specular_f0", "alpha_tangent", "alpha_bitangent", "tangent_deg"}) {
    ASSERT_TRUE(doc["parameters"].contains(name)) << name;
    EXPECT_TRUE(doc["parameters"][name].contains("value")) << name;
    EXPECT_TRUE(doc["parameters"][name].contains("sigma")) << name;
    EXPECT_FALSE(doc["parameters"][name]["unit"].get<std::string>().empty()) << name;
  }
  EXPECT_FALSE(doc["parameters"].contains("sheen_colour"));
  EXPECT_FALSE(doc["parameters"].contains("coat_weight"));
  EXPECT_DOUBLE_EQ(doc["parameters"]["alpha_tangent"]["value"].get<double>(),
                   r.material.alphaTangent);
  EXPECT_DOUBLE_EQ(doc["parameters"]["tangent_deg"]["value"].get<double>(), r.material.tangentDeg);
  EXPECT_EQ(doc["parameters"]["specular_f0"]["value"].size(), 3u);
  EXPECT_DOUBLE_EQ(doc["metrics"]["delta_e"].get<double>(), r.metrics.deltaE);
  EXPECT_DOUBLE_EQ(doc["metrics"]["psnr_db"].get<double>(), r.metrics.psnrDb);
  EXPECT_TRUE(doc["conventions"].contains("tangent"));
  EXPECT_TRUE(doc["conventions"].contains("roughness"));
  EXPECT_EQ(doc["candidates"].size(), r.candidates.size());
}

TEST(MaterialJson, ACoatSaysItsWeightAndAlphaWithUnits) {
  FitResult r = steelFit();
  r.material.model = MaterialModel::GgxCoat;
  r.material.coatWeight = 0.9;
  r.material.coatAlpha = 0.05;
  r.sigmas.coatWeight = 0.01;
  const auto doc = materialJson(r, "coated.exr");
  EXPECT_EQ(doc["model"], "ggx+coat");
  EXPECT_DOUBLE_EQ(doc["parameters"]["coat_weight"]["value"].get<double>(), 0.9);
  EXPECT_DOUBLE_EQ(doc["parameters"]["coat_weight"]["sigma"].get<double>(), 0.01);
  EXPECT_TRUE(doc["parameters"]["coat_alpha"]["sigma"].is_null());
  EXPECT_DOUBLE_EQ(doc["parameters"]["coat_alpha"]["value"].get<double>(), 0.05);
  EXPECT_NE(doc["parameters"]["coat_weight"]["unit"].get<std::string>().find("clearcoatFactor"),
            std::string::npos);
  EXPECT_NE(doc["conventions"]["brdf"].get<std::string>().find("coat"), std::string::npos);
  EXPECT_FALSE(doc["parameters"].contains("sheen_colour"));
}

TEST(MaterialJson, FileIsReplacedWholeAndReadsBack) {
  const auto dir = test::freshTempDir();
  const auto path = dir / "material.json";
  std::ofstream(path) << "old";
  const auto doc = materialJson(steelFit(), "steel.exr");
  writeMaterialJson(path, doc);
  std::ifstream in(path);
  const auto back = nlohmann::json::parse(in);
  EXPECT_EQ(back["model"], "ggx");
  EXPECT_FALSE(std::filesystem::exists(dir / "material.json.tmp"));
}

TEST(MaterialJson, UnwritablePathIsAnErrorNamingIt) {
  const auto dir = test::freshTempDir();
  std::filesystem::create_directories(dir / "taken");
  const auto doc = materialJson(steelFit(), "steel.exr");
  try {
    writeMaterialJson(dir / "taken", doc);
    FAIL() << "wrote over a directory";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("taken"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slicecap::fit
