// sessionMaterial: the fit of a session's exported table and the four files it writes.
#include "slicecap/material_export/session_material.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "../support/test_support.hpp"
#include "slicecap/material_export/material_reader.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::material_export {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(SessionMaterial, FitsTheTableAndWritesItsFilesOnlyWhenAsked) {
  const Abrdf table = models::tabulate(*models::findMaterial("brushed-steel-30"));
  const SessionMaterial material = sessionMaterial(table, "felt-abrdf-b.exr");
  EXPECT_LT(material.fit.metrics.deltaE, 1.0) << "GGX from GGX";
  EXPECT_NE(material.summary.find("dE"), std::string::npos) << material.summary;
  ASSERT_EQ(material.files.size(), 4u);
  const fs::path dir = test::freshTempDir() / "export";
  fs::create_directories(dir);
  EXPECT_TRUE(fs::is_empty(dir)) << "nothing is written before a file's write is called";
  for (const MaterialFile& file : material.files) file.write(dir / ("felt" + file.suffix));
  // The JSON reads back as the fit it holds.
  const fit::FittedMaterial back = readFittedMaterial(dir / "felt-material.json");
  EXPECT_NEAR(back.alphaTangent, material.fit.material.alphaTangent, 1e-6);
  EXPECT_NEAR(back.tangentDeg, material.fit.material.tangentDeg, 1e-6);
  EXPECT_NE(readText(dir / "felt-material.gltf").find("KHR_materials_anisotropy"), std::string::npos);
  EXPECT_NE(readText(dir / "felt-material.mtlx").find("open_pbr_surface"), std::string::npos);
  EXPECT_NE(readText(dir / "felt-material-mitsuba.xml").find("alpha_u"), std::string::npos);
}

TEST(SessionMaterial, ATableThatIsNoBrdfIsAFitErrorNamingIt) {
  Abrdf table;  // all zero: no light reflected
  try {
    sessionMaterial(table, "felt-abrdf-b.exr");
    FAIL() << "an all-zero table was fitted";
  } catch (const fit::FitError& error) {
    EXPECT_NE(std::string(error.what()).find("felt-abrdf-b.exr"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace slicecap::material_export
