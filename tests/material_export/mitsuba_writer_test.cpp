// The Mitsuba snippet: the blend weight and the scaled parts add up to the fit at normal
// incidence, every reflectance stays within [0, 1], and a sheen becomes its GGX stand-in.
// (python/tests loads it in Mitsuba and compares its BSDF with the fit.)
#include "slicecap/material_export/mitsuba_writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

#include "slicecap/fit/sheen_albedo.hpp"
#include "slicecap/material_export/mitsuba_sheen.hpp"

namespace slicecap::material_export {
namespace {

// The numbers of the `occurrence`-th (from 0) element of this name.
std::vector<double> values(const std::string& text, const std::string& name,
                           std::size_t occurrence = 0) {
  const std::regex re("name=\"" + name + "\" value=\"([^\"]+)\"");
  std::sregex_iterator it(text.begin(), text.end(), re);
  for (std::size_t k = 0; k < occurrence && it != std::sregex_iterator(); ++k) ++it;
  EXPECT_TRUE(it != std::sregex_iterator()) << name << " #" << occurrence;
  if (it == std::sregex_iterator()) return {};
  const std::smatch& match = *it;
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

fit::FittedMaterial velvet() {
  fit::FittedMaterial m = paint();
  m.model = fit::MaterialModel::GgxSheen;
  m.diffuseAlbedo = Rgb{0.04, 0.08, 0.05};
  m.specularF0 = Rgb{0.02, 0.03, 0.02};
  m.specularF90 = 0.05;
  m.sheenColour = Rgb{0.12, 0.25, 0.15};  // dim enough that the stand-in's scale is not bounded
  m.sheenRoughness = 0.3;
  // Format version 1's additive sheen: the blend's arithmetic below is the fit's sum; the khr
  // form's dimming has its own test.
  m.sheenForm = fit::SheenForm::Additive;
  return m;
}

bool hasLoss(const MitsubaExport& e, LossKind kind) {
  return std::any_of(e.report.losses.begin(), e.report.losses.end(),
                     [&](const ConversionLoss& l) { return l.kind == kind; });
}

TEST(MitsubaWriter, SheenBecomesTheLeastSquaresGgxStandInAndTheRestStaysASum) {
  const fit::FittedMaterial m = velvet();
  const MitsubaExport e = mitsubaSnippet(m, "v.json");
  const SheenApproximation a =
      approximateSheen(0.3, (1.0 - 0.08 - 0.03) / 0.25, fit::SheenForm::Additive);
  ASSERT_LT(a.scale, (1.0 - 0.08 - 0.03) / 0.25);
  // The stand-in: weight c x reflectance = the approximation's scale x the sheen colour.
  const double c = values(e.text, "weight").at(0);
  const auto reflectance = values(e.text, "specular_reflectance");
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(c * reflectance.at(k), a.scale * m.sheenColour[k], 1e-5);
  EXPECT_NEAR(values(e.text, "alpha").at(0), a.alpha, 1e-5);
  EXPECT_NE(e.text.find("<string name=\"material\" value=\"none\"/>"), std::string::npos);
  // The diffuse + GGX inside, weighted (1 - c): still the fit's albedo and f0 at normal incidence.
  const double w = values(e.text, "weight", 1).at(0);
  EXPECT_NEAR((1.0 - c) * (1.0 - w) * values(e.text, "reflectance").at(1), 0.08, 1e-5);
  const double eta = values(e.text, "eta").at(1);
  EXPECT_NEAR((1.0 - c) * w * std::pow((eta - 1.0) / (eta + 1.0), 2), 0.03, 1e-5);
  EXPECT_NEAR((1.0 - c) * w, 0.05, 1e-5);  // the fit's f90 fits: the grazing value is kept
  EXPECT_TRUE(hasLoss(e, LossKind::SheenForm));
  EXPECT_FALSE(hasLoss(e, LossKind::SheenDropped));
  EXPECT_FALSE(hasLoss(e, LossKind::SpecularColourAtGrazing));
  const std::string& said = e.report.losses.back().detail;
  const std::size_t at = said.find("rms mismatch ");
  ASSERT_NE(at, std::string::npos) << said;
  EXPECT_NEAR(std::stod(said.substr(at + 13)), a.relativeMismatch, 1e-5);
}

// KHR_materials_sheen's layering dims the base by 1 - s max(E(cos_l), E(cos_v)); a blend cannot
// vary it with the directions, so the rest is dimmed by its radiance-weighted mean over the grid,
// and the stand-in approximates the khr lobe (the Charlie visibility).
TEST(MitsubaWriter, AKhrSheenDimsTheRestByTheMeanOfTheExtensionsScaling) {
  fit::FittedMaterial m = velvet();
  m.sheenForm = fit::SheenForm::Khr;
  const MitsubaExport e = mitsubaSnippet(m, "v.json");
  double sum = 0.0, weights = 0.0;
  for (int i = 0; i < bonn::kDirectionCount; ++i)
    for (int j = 0; j < bonn::kDirectionCount; ++j) {
      const double cl = toUnitVector(bonn::direction(i)).z, cv = toUnitVector(bonn::direction(j)).z;
      sum += cl * (1.0 - 0.25 * std::max(fit::sheenAlbedo(cl, 0.3), fit::sheenAlbedo(cv, 0.3)));
      weights += cl;
    }
  const double scaling = sum / weights;
  ASSERT_LT(scaling, 0.99);
  const SheenApproximation a = approximateSheen(0.3, (1.0 - scaling * (0.08 + 0.03)) / 0.25,
                                                fit::SheenForm::Khr);
  const double c = values(e.text, "weight").at(0);
  const auto reflectance = values(e.text, "specular_reflectance");
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(c * reflectance.at(k), a.scale * m.sheenColour[k], 1e-5);
  const double w = values(e.text, "weight", 1).at(0);
  EXPECT_NEAR((1.0 - c) * (1.0 - w) * values(e.text, "reflectance").at(1), 0.08 * scaling, 1e-5);
  EXPECT_NEAR((1.0 - c) * w, 0.05 * scaling, 1e-5);
  EXPECT_TRUE(std::any_of(e.report.losses.begin(), e.report.losses.end(), [](const ConversionLoss& l) {
    return l.kind == LossKind::SheenForm && l.detail.find("1 - s E") != std::string::npos;
  }));
  // The additive form's stand-in is another lobe (Ashikhmin's visibility).
  EXPECT_NE(approximateSheen(0.3, 10.0, fit::SheenForm::Khr).scale,
            approximateSheen(0.3, 10.0, fit::SheenForm::Additive).scale);
}

TEST(MitsubaWriter, SheenAloneGetsTheWholeBlendAndStaysFinite) {
  fit::FittedMaterial m = velvet();
  m.diffuseAlbedo = Rgb::gray(0.0);
  m.specularF0 = Rgb::gray(0.0);
  m.specularF90 = 0.0;
  m.sheenColour = Rgb{0.6, 0.9, 0.7};  // bright: the stand-in's scale reaches the room's bound
  const MitsubaExport e = mitsubaSnippet(m, "v.json");
  EXPECT_NEAR(values(e.text, "weight").at(0), 1.0, 1e-9);
  EXPECT_EQ(e.text.find("nan"), std::string::npos) << e.text;
  EXPECT_EQ(e.text.find("inf"), std::string::npos) << e.text;
  for (double r : values(e.text, "reflectance")) EXPECT_EQ(r, 0.0);
}

TEST(MitsubaWriter, SheenWithNoRoomIsDroppedAndTheSnippetIsTheGgxOne) {
  fit::FittedMaterial m = velvet();
  m.diffuseAlbedo = Rgb{0.5, 0.97, 0.5};  // albedo + f0 = 1: nothing left for the sheen
  const MitsubaExport e = mitsubaSnippet(m, "v.json");
  EXPECT_TRUE(hasLoss(e, LossKind::SheenDropped));
  EXPECT_FALSE(hasLoss(e, LossKind::SheenForm));
  fit::FittedMaterial ggx = m;
  ggx.model = fit::MaterialModel::Ggx;
  EXPECT_EQ(e.text, mitsubaSnippet(ggx, "v.json").text);
}

fit::FittedMaterial lacquer() {
  fit::FittedMaterial m = paint();
  m.model = fit::MaterialModel::GgxCoat;
  m.diffuseAlbedo = Rgb{0.2, 0.1, 0.05};
  m.coatWeight = 0.5;
  m.coatAlpha = 0.04;
  return m;
}

TEST(MitsubaWriter, CoatIsBlendedAroundTheRestWhichStaysTheFitsSum) {
  const MitsubaExport e = mitsubaSnippet(lacquer(), "l.json");
  // The outer blend: the coat's weight, 0.5 (room: 1 - 0.2 - 0.05).
  const double c = values(e.text, "weight", 0).at(0);
  EXPECT_NEAR(c, 0.5, 1e-9);
  // Inside, the diffuse + GGX blend divided by (1 - c): the fit's albedo and grazing value again.
  const double w = values(e.text, "weight", 1).at(0);
  EXPECT_NEAR((1.0 - c) * (1.0 - w) * values(e.text, "reflectance").at(0), 0.2, 1e-5);
  EXPECT_NEAR((1.0 - c) * w, 0.3, 1e-5);
  EXPECT_FALSE(hasLoss(e, LossKind::SpecularColourAtGrazing));
  // The coat: a roughconductor after the GGX one, of the coat's alpha and a dielectric's eta.
  EXPECT_NEAR(values(e.text, "alpha").at(0), 0.04, 1e-12);
  EXPECT_NEAR(values(e.text, "eta", 1).at(0), 1.5, 1e-12);
  // One BSDF is the material the scene refers to: the outer blend.
  const std::string outer = "<bsdf type=\"blendbsdf\" id=\"slicecap_fit\">";
  ASSERT_NE(e.text.find(outer), std::string::npos);
  EXPECT_EQ(e.text.find(outer), e.text.rfind(outer));
  EXPECT_EQ(e.text.find("id=\"slicecap_fit\">"), e.text.rfind("id=\"slicecap_fit\">"));
  EXPECT_TRUE(hasLoss(e, LossKind::CoatForm));
  for (double r : values(e.text, "reflectance")) EXPECT_LE(r, 1.0);
}

TEST(MitsubaWriter, ACoatWithNoRoomIsReducedAndSaysSo) {
  fit::FittedMaterial m = lacquer();
  m.coatWeight = 0.9;  // the room is 1 - 0.2 - 0.05 = 0.75
  const MitsubaExport e = mitsubaSnippet(m, "l.json");
  EXPECT_NEAR(values(e.text, "weight", 0).at(0), 0.75, 1e-9);
  EXPECT_TRUE(std::any_of(e.report.losses.begin(), e.report.losses.end(),
                          [](const ConversionLoss& l) {
                            return l.kind == LossKind::CoatForm &&
                                   l.detail.find("reduced to 0.75") != std::string::npos;
                          }));
  for (double r : values(e.text, "reflectance")) EXPECT_LE(r, 1.0 + 1e-9);
}

TEST(MitsubaWriter, ACoatOverASheenNestsThreeBlendsAndAFullCoatStaysFinite) {
  fit::FittedMaterial m = velvet();  // room: 1 - 0.08 - 0.03 = 0.89
  m.model = fit::MaterialModel::GgxSheenCoat;
  m.coatWeight = 0.3;
  m.coatAlpha = 0.05;
  const MitsubaExport e = mitsubaSnippet(m, "cv.json");
  std::size_t blends = 0;
  for (std::size_t at = 0; (at = e.text.find("type=\"blendbsdf\"", at)) != std::string::npos; ++at)
    ++blends;
  EXPECT_EQ(blends, 3u);  // coat around [sheen around [diffuse + GGX]]
  EXPECT_NEAR(values(e.text, "weight", 0).at(0), 0.3, 1e-9);
  EXPECT_TRUE(hasLoss(e, LossKind::SheenForm));
  EXPECT_TRUE(hasLoss(e, LossKind::CoatForm));
  for (double r : values(e.text, "reflectance")) EXPECT_LE(r, 1.0 + 1e-9);

  // Nothing but the coat: its blend weight is 1 and the rest, divided by 0, is left at 0.
  fit::FittedMaterial bare = lacquer();
  bare.diffuseAlbedo = Rgb::gray(0.0);
  bare.specularF0 = Rgb::gray(0.0);
  bare.specularF90 = 0.0;
  bare.coatWeight = 1.0;
  const MitsubaExport full = mitsubaSnippet(bare, "c.json");
  EXPECT_NEAR(values(full.text, "weight", 0).at(0), 1.0, 1e-9);
  EXPECT_EQ(full.text.find("nan"), std::string::npos) << full.text;
  EXPECT_EQ(full.text.find("inf"), std::string::npos) << full.text;
}

}  // namespace
}  // namespace slicecap::material_export
