// The MaterialX document: OpenPBR's and standard_surface's anisotropy inverted from the fitted
// alphas, the tangent rotation, and the losses. (python/tests validates it with MaterialX itself.)
#include "slicecap/material_export/mtlx_writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <regex>

namespace slicecap::material_export {
namespace {

fit::FittedMaterial brushed() {
  fit::FittedMaterial m;
  m.diffuseAlbedo = Rgb{0.02, 0.02, 0.02};
  m.specularF0 = Rgb{0.9, 0.6, 0.5};
  m.specularF90 = 1.0;
  m.alphaTangent = 0.4;
  m.alphaBitangent = 0.1;
  m.tangentDeg = 120.0;
  return m;
}

// The value of input `name` in the node that starts with `node`.
double inputValue(const std::string& text, const std::string& node, const std::string& name) {
  const std::size_t at = text.find(node);
  EXPECT_NE(at, std::string::npos) << node;
  const std::regex re("<input name=\"" + name + "\" type=\"float\" value=\"([^\"]+)\"");
  std::smatch match;
  const std::string rest = text.substr(at);
  EXPECT_TRUE(std::regex_search(rest, match, re)) << name;
  return std::stod(match[1]);
}

TEST(MtlxWriter, OpenPbrAnisotropyReproducesTheFittedAlphas) {
  const std::string text = mtlxDocument(brushed(), "b.json").text;
  const double r = inputValue(text, "<open_pbr_surface", "specular_roughness");
  const double a = inputValue(text, "<open_pbr_surface", "specular_roughness_anisotropy");
  // NG_open_pbr_anisotropy: alpha_x = r^2 sqrt(2 / (1 + (1 - a)^2)), alpha_y = (1 - a) alpha_x.
  const double alphaX = r * r * std::sqrt(2.0 / (1.0 + (1.0 - a) * (1.0 - a)));
  EXPECT_NEAR(alphaX, 0.4, 1e-5);
  EXPECT_NEAR((1.0 - a) * alphaX, 0.1, 1e-5);
  EXPECT_NE(text.find("<input name=\"geometry_tangent\" type=\"vector3\" nodename=\"fitted_tangent\""),
            std::string::npos);
}

// The tangent is cos(a) T + sin(a) B (normalised), not rotate3d, whose direction MaterialX's own
// code generators and its specification disagree on (python/tests runs the generated code).
TEST(MtlxWriter, TangentIsTurnedTowardTheBitangentWithoutRotate3d) {
  const std::string text = mtlxDocument(brushed(), "b.json").text;
  EXPECT_EQ(text.find("rotate3d"), std::string::npos);
  const double cosine = inputValue(text, "<multiply name=\"tangent_share\"", "in2");
  const double sine = inputValue(text, "<multiply name=\"bitangent_share\"", "in2");
  EXPECT_NEAR(std::atan2(sine, cosine) * 180.0 / std::numbers::pi, 120.0, 1e-4);
  EXPECT_NE(text.find("<bitangent name=\"surface_bitangent\""), std::string::npos);
  EXPECT_NE(text.find("<input name=\"tangent\" type=\"vector3\" nodename=\"fitted_tangent\""),
            std::string::npos);
}

TEST(MtlxWriter, StandardSurfaceAnisotropyAndRotation) {
  const std::string text = mtlxDocument(brushed(), "b.json").text;
  const double r = inputValue(text, "<standard_surface", "specular_roughness");
  const double a = inputValue(text, "<standard_surface", "specular_anisotropy");
  // mx_roughness_anisotropy: alpha_x = r^2 / sqrt(1 - a), alpha_y = r^2 sqrt(1 - a).
  EXPECT_NEAR(r * r / std::sqrt(1.0 - a), 0.4, 1e-5);
  EXPECT_NEAR(r * r * std::sqrt(1.0 - a), 0.1, 1e-5);
  // The turn is in the tangent fed to it; its own rotation (rotate3d inside its graph) stays 0.
  EXPECT_EQ(inputValue(text, "<standard_surface", "specular_rotation"), 0.0);
}

TEST(MtlxWriter, ExtremeAnisotropyIsClampedAndReported) {
  fit::FittedMaterial m = brushed();
  m.alphaBitangent = 0.004;  // ratio 0.01 < 0.02
  const MtlxExport e = mtlxDocument(m, "b.json");
  EXPECT_NEAR(inputValue(e.text, "<standard_surface", "specular_anisotropy"), 0.98, 1e-9);
  EXPECT_TRUE(std::any_of(e.report.losses.begin(), e.report.losses.end(),
                          [](const ConversionLoss& l) { return l.kind == LossKind::AnisotropyClamped; }));
}

TEST(MtlxWriter, ASourceWithDoubleDashesKeepsTheCommentWellFormed) {
  const std::string text = mtlxDocument(brushed(), "a--b--.json").text;
  const std::size_t open = text.find("<!--"), close = text.find("-->");
  ASSERT_NE(close, std::string::npos);
  EXPECT_EQ(text.substr(open + 4, close - open - 4).find("--"), std::string::npos);
}

TEST(MtlxWriter, SheenBecomesFuzz) {
  fit::FittedMaterial m = brushed();
  m.model = fit::MaterialModel::GgxSheen;
  m.sheenColour = Rgb{0.5, 0.5, 0.5};
  m.sheenRoughness = 0.4;
  const MtlxExport e = mtlxDocument(m, "b.json");
  EXPECT_NEAR(inputValue(e.text, "<open_pbr_surface", "fuzz_roughness"), 0.4, 1e-9);
  EXPECT_NEAR(inputValue(e.text, "<standard_surface", "sheen_roughness"), 0.4, 1e-9);
}

TEST(MtlxWriter, CoatBecomesBothSurfacesCoatOfIor15) {
  fit::FittedMaterial m = brushed();
  EXPECT_EQ(mtlxDocument(m, "b.json").text.find("coat"), std::string::npos);
  m.model = fit::MaterialModel::GgxCoat;
  m.coatWeight = 0.8;
  m.coatAlpha = 0.09;
  const MtlxExport e = mtlxDocument(m, "b.json");
  EXPECT_NEAR(inputValue(e.text, "<open_pbr_surface", "coat_weight"), 0.8, 1e-9);
  EXPECT_NEAR(inputValue(e.text, "<open_pbr_surface", "coat_roughness"), 0.3, 1e-9);
  EXPECT_NEAR(inputValue(e.text, "<open_pbr_surface", "coat_ior"), 1.5, 1e-9);
  EXPECT_NEAR(inputValue(e.text, "<standard_surface", "coat"), 0.8, 1e-9);
  EXPECT_NEAR(inputValue(e.text, "<standard_surface", "coat_roughness"), 0.3, 1e-9);
  EXPECT_NEAR(inputValue(e.text, "<standard_surface", "coat_IOR"), 1.5, 1e-9);
  EXPECT_TRUE(std::any_of(e.report.losses.begin(), e.report.losses.end(),
                          [](const ConversionLoss& l) { return l.kind == LossKind::CoatForm; }));
}

// OpenPBR changes the base under its coat (eta_s = mix(n, n / 1.5 or 1.5 / n, C); the base
// roughness r' = mix(r, (r^4 + 2 rc^4)^(1/4), C)): the inputs written must give back, through
// those, what the same fit without a coat writes.
TEST(MtlxWriter, OpenPbrsBaseUnderItsCoatIsTheFitsBase) {
  for (const double f0 : {0.04, 0.02, 0.6}) {
    fit::FittedMaterial m = brushed();
    m.specularF0 = Rgb::gray(f0);
    const std::string bare = mtlxDocument(m, "b.json").text;
    m.model = fit::MaterialModel::GgxCoat;
    m.coatWeight = 0.8;
    m.coatAlpha = 0.04;
    const std::string coated = mtlxDocument(m, "b.json").text;
    const double c = inputValue(coated, "<open_pbr_surface", "coat_weight");
    const double n = inputValue(coated, "<open_pbr_surface", "specular_ior");
    const double etaS = (1.0 - c) * n + c * (n > 1.5 ? n / 1.5 : 1.5 / n);
    EXPECT_NEAR(etaS, inputValue(bare, "<open_pbr_surface", "specular_ior"), 1e-4) << f0;
    const double rc = inputValue(coated, "<open_pbr_surface", "coat_roughness");
    const double r = inputValue(coated, "<open_pbr_surface", "specular_roughness");
    const double widened = (1.0 - c) * r + c * std::pow(std::pow(r, 4) + 2 * std::pow(rc, 4), 0.25);
    EXPECT_NEAR(widened, inputValue(bare, "<open_pbr_surface", "specular_roughness"), 1e-4) << f0;
    // standard_surface leaves its base alone under the coat (coat_affect_* default 0).
    EXPECT_EQ(inputValue(coated, "<standard_surface", "specular_IOR"),
              inputValue(bare, "<standard_surface", "specular_IOR"));
  }
}

TEST(MtlxWriter, ABaseFainterThanOpenPbrAllowsUnderItsCoatIsReported) {
  fit::FittedMaterial m = brushed();
  m.specularF0 = Rgb::gray(1e-4);  // IOR 1.02: under coat_weight 0.8, eta_s is at least 1.1
  m.model = fit::MaterialModel::GgxCoat;
  m.coatWeight = 0.8;
  m.coatAlpha = 0.04;
  const MtlxExport e = mtlxDocument(m, "b.json");
  EXPECT_TRUE(std::any_of(e.report.losses.begin(), e.report.losses.end(),
                          [](const ConversionLoss& l) {
                            return l.kind == LossKind::CoatForm &&
                                   l.detail.find("comes nearest") != std::string::npos;
                          }));
  EXPECT_NEAR(inputValue(e.text, "<open_pbr_surface", "specular_ior"), 1.5, 1e-9);
}

}  // namespace
}  // namespace slicecap::material_export
