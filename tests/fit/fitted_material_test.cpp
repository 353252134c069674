// The fitted material's BRDF is the built-in GGX (and sheen) lobe, and its canonical form is the
// same BRDF written with the tangent on the larger alpha.
#include "slicecap/fit/fitted_material.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::fit {
namespace {

double largestDifference(const Abrdf& a, const Abrdf& b) {
  double largest = 0.0;
  for (std::size_t i = 0; i < a.values().size(); ++i)
    largest = std::max(largest, double(std::abs(a.values()[i] - b.values()[i])));
  return largest;
}

FittedMaterial steel() {
  FittedMaterial m;
  m.diffuseAlbedo = {0.03, 0.04, 0.05};
  m.specularF0 = {0.56, 0.57, 0.58};
  m.alphaTangent = 0.1;
  m.alphaBitangent = 0.4;
  m.tangentDeg = 30.0;
  return m;
}

TEST(FittedMaterial, GgxIsTheBuiltInGgxLobe) {
  const FittedMaterial m = steel();
  const auto model = models::makeAnisotropicGgx(m.diffuseAlbedo, m.specularF0, 0.1, 0.4, 30.0);
  EXPECT_LT(largestDifference(tabulate(m), models::tabulate(*model)), 1e-4);
}

TEST(FittedMaterial, SheenTermIsTheBuiltInSheen) {
  FittedMaterial m;
  m.model = MaterialModel::GgxSheen;
  m.diffuseAlbedo = {0.15, 0.01, 0.02};
  m.specularF0 = {0.0, 0.0, 0.0};  // no specular at all: the GGX term vanishes
  m.specularF90 = 0.0;
  m.sheenColour = {0.7, 0.15, 0.15};
  m.sheenRoughness = 0.3;
  m.sheenForm = SheenForm::Additive;  // format version 1's form is the built-in sheen's
  const auto model = models::makeSheen(m.diffuseAlbedo, m.sheenColour, 0.3);
  EXPECT_LT(largestDifference(tabulate(m), models::tabulate(*model)), 1e-4);
}

// glTF 2.0 Appendix B's isotropic D_GGX V_GGX, written out here from the specification and not
// from lobe_terms.hpp.
double appendixBGgx(const UnitVector& l, const UnitVector& v, double alpha) {
  const double hx = l.x + v.x, hy = l.y + v.y, hz = l.z + v.z;
  const double nh = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
  const double a2 = alpha * alpha;
  const double d = a2 / (std::numbers::pi * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2));
  const double vis = 0.5 / (l.z * std::sqrt(v.z * v.z * (1.0 - a2) + a2) +
                            v.z * std::sqrt(l.z * l.z * (1.0 - a2) + a2));
  return d * vis;
}

UnitVector at(double thetaDeg, double phiDeg) {
  const double t = thetaDeg * std::numbers::pi / 180.0, p = phiDeg * std::numbers::pi / 180.0;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

TEST(FittedMaterial, CoatIsTheClearcoatLayeringOfGltf) {
  // KHR_materials_clearcoat: mix(base, coat_brdf, w (0.04 + 0.96 (1 - n.v)^5)).
  FittedMaterial coated = steel();
  coated.model = MaterialModel::GgxCoat;
  coated.coatWeight = 0.7;
  coated.coatAlpha = 0.05;
  const FittedMaterial base = steel();
  for (const double thetaI : {0.0, 30.0, 60.0, 80.0})
    for (const double thetaV : {5.0, 30.0, 60.0, 85.0})
      for (const double phiV : {0.0, 170.0, 250.0}) {
        const UnitVector l = at(thetaI, 40.0), v = at(thetaV, phiV);
        const double fc = 0.04 + 0.96 * std::pow(1.0 - v.z, 5);
        const double share = 0.7 * fc;
        const Rgb got = coated.evaluate(l, v), under = base.evaluate(l, v);
        for (std::size_t c = 0; c < 3; ++c) {
          const double expected = under[c] * (1.0 - share) + share * appendixBGgx(l, v, 0.05);
          EXPECT_NEAR(got[c], expected, 1e-9 * std::max(1.0, expected))
              << thetaI << " " << thetaV << " " << phiV;
        }
      }
}

TEST(FittedMaterial, CoatOfWeightZeroIsTheBaseAndModelNamesSayTheirTerms) {
  FittedMaterial coated = steel();
  coated.model = MaterialModel::GgxCoat;
  coated.coatWeight = 0.0;
  EXPECT_EQ(largestDifference(tabulate(coated), tabulate(steel())), 0.0);
  EXPECT_EQ(toString(MaterialModel::GgxSheenCoat), "ggx+sheen+coat");
  EXPECT_EQ(modelWith(true, true), MaterialModel::GgxSheenCoat);
  EXPECT_EQ(modelWith(false, true), MaterialModel::GgxCoat);
  EXPECT_TRUE(hasSheen(MaterialModel::GgxSheenCoat));
  EXPECT_FALSE(hasSheen(MaterialModel::GgxCoat));
  EXPECT_TRUE(hasCoat(MaterialModel::GgxCoat));
  EXPECT_FALSE(hasCoat(MaterialModel::GgxSheen));
}

TEST(FittedMaterial, CanonicalPutsTheTangentOnTheLargerAlphaAndKeepsTheBrdf) {
  const FittedMaterial m = steel();
  const FittedMaterial c = m.canonical();
  EXPECT_DOUBLE_EQ(c.alphaTangent, 0.4);
  EXPECT_DOUBLE_EQ(c.alphaBitangent, 0.1);
  EXPECT_DOUBLE_EQ(c.tangentDeg, 120.0);
  EXPECT_LT(largestDifference(tabulate(m), tabulate(c)), 1e-5);
}

TEST(FittedMaterial, CanonicalWrapsTheTangentIntoAHalfTurn) {
  FittedMaterial m = steel().canonical();
  m.tangentDeg = -100.0;
  EXPECT_NEAR(m.canonical().tangentDeg, 80.0, 1e-12);
  m.tangentDeg = 400.0;
  EXPECT_NEAR(m.canonical().tangentDeg, 40.0, 1e-12);
  // The lobe turned by a half turn is the same lobe.
  FittedMaterial turned = m;
  turned.tangentDeg += 180.0;
  EXPECT_LT(largestDifference(tabulate(m), tabulate(turned)), 1e-5);
}

TEST(FittedMaterial, TangentDifferenceIsModuloAHalfTurn) {
  EXPECT_NEAR(tangentDifferenceDeg(179.0, 1.0), -2.0, 1e-12);
  EXPECT_NEAR(tangentDifferenceDeg(1.0, 179.0), 2.0, 1e-12);
  EXPECT_NEAR(tangentDifferenceDeg(100.0, 10.0), 90.0, 1e-12);
  EXPECT_NEAR(tangentDifferenceDeg(30.0, 210.0), 0.0, 1e-12);
}

}  // namespace
}  // namespace slicecap::fit
