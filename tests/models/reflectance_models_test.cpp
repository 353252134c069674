// Physical properties of the analytic models: reciprocity, isotropy, energy of Lambert, rotation.
#include "slicecap/models/reflectance_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slicecap/models/model_error.hpp"

namespace slicecap::models {
namespace {

std::vector<NamedMaterial> allMaterials() {
  auto all = anisotropicMaterials();
  for (auto& m : isotropicMaterials())
    all.push_back(m);
  return all;
}

TEST(Models, EveryBuiltInMaterialIsReciprocalPositiveAndFinite) {
  for (const NamedMaterial& m : allMaterials()) {
    const Abrdf t = tabulate(*m.model);
    for (int l = 0; l < 81; ++l) {
      for (int v = 0; v < 81; ++v) {
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(std::isfinite(t.channel(l, v, c))) << m.name;
          ASSERT_GE(t.channel(l, v, c), 0.0f) << m.name;
          ASSERT_NEAR(t.channel(l, v, c), t.channel(v, l, c), 1e-5f * (1 + t.channel(l, v, c)))
              << m.name;
        }
      }
    }
  }
}

TEST(Models, IsotropicOnesDependOnlyOnTheAzimuthDifference) {
  for (const NamedMaterial& m : allMaterials()) {
    // Near the specular ridge, where every lobe is awake.
    const Direction l{45, 20}, v{50, 215};
    const Direction lTurned{45, 20 + 77}, vTurned{50, 215 + 77};
    const Rgb a = m.model->evaluate(toUnitVector(l), toUnitVector(v));
    const Rgb b = m.model->evaluate(toUnitVector(lTurned), toUnitVector(vTurned));
    if (m.model->isIsotropic()) {
      EXPECT_NEAR(a.g(), b.g(), 1e-9 * (1 + a.g())) << m.name;
    } else {
      EXPECT_GT(std::abs(a.g() - b.g()), 1e-4 * a.g()) << m.name << " should be anisotropic";
    }
  }
}

TEST(Models, LambertIsAlbedoOverPi) {
  const auto lambert = makeLambert({0.5, 0.25, 1.0});
  const Rgb v = lambert->evaluate(toUnitVector({30, 10}), toUnitVector({60, 200}));
  EXPECT_DOUBLE_EQ(v.r(), 0.5 / std::numbers::pi);
  EXPECT_DOUBLE_EQ(v.b(), 1.0 / std::numbers::pi);
}

TEST(Models, AnisotropicLobesFollowTheirTangent) {
  // Rotating the tangent by 90 deg swaps alpha_x and alpha_y.
  const auto a = makeWard({0, 0, 0}, {1, 1, 1}, 0.1, 0.4, 0.0);
  const auto b = makeWard({0, 0, 0}, {1, 1, 1}, 0.4, 0.1, 90.0);
  const UnitVector l = toUnitVector({40, 10}), v = toUnitVector({50, 170});
  EXPECT_NEAR(a->evaluate(l, v).r(), b->evaluate(l, v).r(), 1e-9);
  const auto g1 = makeAnisotropicGgx({0, 0, 0}, {1, 1, 1}, 0.1, 0.4, 0.0);
  const auto g2 = makeAnisotropicGgx({0, 0, 0}, {1, 1, 1}, 0.4, 0.1, 90.0);
  EXPECT_NEAR(g1->evaluate(l, v).r(), g2->evaluate(l, v).r(), 1e-9);
}

TEST(Models, GgxConservesEnergyAtNormalIncidence) {
  // Directional albedo of a white GGX mirror lobe (f0 = 1) at normal incidence: close to 1, not
  // above.
  const auto ggx = makeAnisotropicGgx({0, 0, 0}, {1, 1, 1}, 0.2, 0.3, 0.0);
  const UnitVector l{0, 0, 1};
  double albedo = 0.0;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) * (std::numbers::pi / 2) / n;
    for (int j = 0; j < n; ++j) {
      const double phi = (j + 0.5) * 2 * std::numbers::pi / n;
      const UnitVector v{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta)};
      albedo += ggx->evaluate(l, v).r() * std::cos(theta) * std::sin(theta) *
                (std::numbers::pi / 2 / n) * (2 * std::numbers::pi / n);
    }
  }
  EXPECT_GT(albedo, 0.9);
  EXPECT_LE(albedo, 1.0 + 1e-3);
}

TEST(Models, RejectsNonPositiveRoughness) {
  EXPECT_THROW(makeWard({0, 0, 0}, {1, 1, 1}, 0.0, 0.1), models::ModelError);
  EXPECT_THROW(makeAnisotropicGgx({0, 0, 0}, {1, 1, 1}, 0.1, -1.0), models::ModelError);
  EXPECT_EQ(findMaterial("no-such-material"), nullptr);
}

}  // namespace
}  // namespace slicecap::models
