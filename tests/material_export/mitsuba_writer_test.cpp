// The Mitsuba snippet: the blend weight and the scaled parts add up to the fit at normal
// incidence, every reflectance stays within [0, 1], and the sheen's absence is reported.
// (python/tests loads it in Mitsuba and compares its BSDF with the fit.)
#include "slicecap/material_export/mitsuba_writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

namespace slicecap::material_export {
namespace {

std::vector<double> values(const std::string& text, const std::string& name) {
  const std::regex re("name=\"" + name + "\" value=\"([^\"]+)\"");
  std::smatch match;
  EXPECT_TRUE(std::regex_search(text, match, re)) << name;
  std::vector<double> out;
  std::string list = match[1];
  std::replace(list.begin(), list.end(), ',', ' ');
  std::istringstream in(list);
  for (double v; in >> v;) out.push_back(v);
  return out;
}

fit::FittedMaterial paint() {
  fit::FittedMaterial m;
  m.diffuseAlbedo = Rgb{0.6, 0.3, 0.1};
  m.specularF0 = Rgb::gray(0.05);
  m.specularF90 = 0.3;
  m.alphaTangent = 0.3;
  m.alphaBitangent = 0.15;
  m.tangentDeg = 70.0;
  return m;
}

TEST(MitsubaWriter, BlendAddsUpToTheFitAtNormalIncidence) {
  const std::string text = mitsubaSnippet(paint(), "p.json").text;
  const double w = values(text, "weight").at(0);
  EXPECT_NEAR(w, 0.3, 1e-9);  // f90 fits in [max f0, 1 - max albedo] = [0.05, 0.4]
  const auto reflectance = values(text, "reflectance");
  EXPECT_NEAR((1.0 - w) * reflectance.at(0), 0.6, 1e-5);
  EXPECT_NEAR((1.0 - w) * reflectance.at(2), 0.1, 1e-5);
  const double eta = values(text, "eta").at(1);
  const double f0 = std::pow((eta - 1.0) / (eta + 1.0), 2);
  EXPECT_NEAR(w * f0, 0.05, 1e-5);
  EXPECT_EQ(values(text, "alpha_u").at(0), 0.3);
  EXPECT_EQ(values(text, "alpha_v").at(0), 0.15);
  EXPECT_NE(text.find("<rotate z=\"1\" angle=\"70\"/>"), std::string::npos);
}

TEST(MitsubaWriter, BrightMaterialMovesTheGrazingValueAndSaysSo) {
  fit::FittedMaterial m = paint();
  m.specularF90 = 1.0;  // 1 - max albedo = 0.4: w cannot be 1
  const MitsubaExport e = mitsubaSnippet(m, "p.json");
  EXPECT_NEAR(values(e.text, "weight").at(0), 0.4, 1e-9);
  for (double r : values(e.text, "reflectance")) EXPECT_LE(r, 1.0);
  EXPECT_TRUE(std::any_of(e.report.losses.begin(), e.report.losses.end(), [](const ConversionLoss& l) {
    return l.kind == LossKind::SpecularColourAtGrazing;
  }));
}

TEST(MitsubaWriter, SheenIsApproximatedAndSaysSo) {
  fit::FittedMaterial m = paint();
  m.model = fit::MaterialModel::GgxSheen;
  m.sheenColour = Rgb{0.2, 0.2, 0.2};
  const MitsubaExport e = mitsubaSnippet(m, "p.json");
  EXPECT_TRUE(std::any_of(e.report.losses.begin(), e.report.losses.end(),
                          [](const ConversionLoss& l) { return l.kind == LossKind::SheenForm; }));
}

}  // namespace
}  // namespace slicecap::material_export
