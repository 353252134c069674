// The fitted material's BRDF is the built-in GGX (and sheen) lobe, and its canonical form is the
// same BRDF written with the tangent on the larger alpha.
#include "slicecap/fit/fitted_material.hpp"

#include <gtest/gtest.h>

#include <cmath>

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
  const auto model = models::makeSheen(m.diffuseAlbedo, m.sheenColour, 0.3);
  EXPECT_LT(largestDifference(tabulate(m), models::tabulate(*model)), 1e-4);
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
