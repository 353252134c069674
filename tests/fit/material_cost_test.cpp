// The fit's hand-written Jacobian (lib/fit/src/material_cost.cpp): every parameter block layout
// ({ggx}, {ggx, sheen}, {ggx, coat}, {ggx, sheen, coat}) against central finite differences of
// the residuals, the sheen in both of its forms (KHR_materials_sheen's layering, whose albedo
// scaling moves the base's derivatives too, and the additive form of format version 1). The Levenberg-Marquardt solve would still converge, only more slowly, with a
// wrong derivative, so the fit's tests alone would not show one.
#include "material_cost.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "fit_data.hpp"
#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::fit::detail {
namespace {

// A coated, sheened table: every term of the model is seen by the residuals.
FitData someData() {
  FittedMaterial m;
  m.model = MaterialModel::GgxSheenCoat;
  m.diffuseAlbedo = {0.3, 0.1, 0.05};
  m.specularF0 = {0.2, 0.15, 0.1};
  m.specularF90 = 0.8;
  m.alphaTangent = 0.4;
  m.alphaBitangent = 0.15;
  m.tangentDeg = 30.0;
  m.sheenColour = {0.2, 0.3, 0.1};
  m.sheenRoughness = 0.4;
  m.coatWeight = 0.7;
  m.coatAlpha = 0.08;
  // Every 7th pair: 937 pairs, all kinds of geometry, a fast test.
  return everyNthPair(makeFitData(tabulate(m)), 7);
}

struct Layout {
  bool sheen, coat;
  SheenForm form = SheenForm::Khr;
};

// The layout's name. gtest would otherwise print the struct's bytes, padding included, into the
// names ctest lists, which then differ between builds (x86-64 and aarch64 did).
std::string layoutName(const Layout& l) {
  const std::string sheen =
      l.sheen ? (l.form == SheenForm::Khr ? "KhrSheen" : "AdditiveSheen") : "NoSheen";
  return sheen + (l.coat ? "Coat" : "NoCoat");
}
void PrintTo(const Layout& l, std::ostream* os) { *os << layoutName(l); }

class MaterialCostJacobian : public ::testing::TestWithParam<Layout> {};

TEST_P(MaterialCostJacobian, EqualsCentralDifferences) {
  const Layout layout = GetParam();
  const FitData data = someData();
  const MaterialCost cost(data, layout.sheen, layout.coat, layout.form);
  // A point off the table's own parameters (non-zero residuals) and inside every bound.
  std::vector<std::vector<double>> blocks{
      {0.25, 0.12, 0.07, 0.18, 0.12, 0.09, std::log(0.35), std::log(0.2), 0.6, 0.7}};
  if (layout.sheen) blocks.push_back({0.15, 0.25, 0.12, std::log(0.5)});
  if (layout.coat) blocks.push_back({0.6, std::log(0.1)});
  const auto n = static_cast<std::size_t>(data.residualCount());
  std::vector<const double*> pointers;
  for (const auto& b : blocks) pointers.push_back(b.data());
  std::vector<std::vector<double>> jacobians;
  std::vector<double*> jacobianPointers;
  for (const auto& b : blocks) jacobians.emplace_back(n * b.size());
  for (auto& j : jacobians) jacobianPointers.push_back(j.data());
  std::vector<double> residuals(n), plus(n), minus(n);
  ASSERT_TRUE(cost.Evaluate(pointers.data(), residuals.data(), jacobianPointers.data()));

  for (std::size_t b = 0; b < blocks.size(); ++b) {
    for (std::size_t p = 0; p < blocks[b].size(); ++p) {
      const double x = blocks[b][p], h = 1e-6 * std::max(1.0, std::abs(x));
      blocks[b][p] = x + h;
      cost.Evaluate(pointers.data(), plus.data(), nullptr);
      blocks[b][p] = x - h;
      cost.Evaluate(pointers.data(), minus.data(), nullptr);
      blocks[b][p] = x;
      double error = 0.0, norm = 0.0;
      for (std::size_t r = 0; r < n; ++r) {
        const double numeric = (plus[r] - minus[r]) / (2.0 * h);
        const double analytic = jacobians[b][r * blocks[b].size() + p];
        error += (analytic - numeric) * (analytic - numeric);
        norm += numeric * numeric;
      }
      ASSERT_GT(norm, 0.0) << "block " << b << " parameter " << p << " moves no residual";
      EXPECT_LT(std::sqrt(error / norm), 1e-5) << "block " << b << " parameter " << p;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryBlockLayout, MaterialCostJacobian,
                         ::testing::Values(Layout{false, false}, Layout{true, false},
                                           Layout{false, true}, Layout{true, true},
                                           Layout{true, false, SheenForm::Additive},
                                           Layout{true, true, SheenForm::Additive}),
                         [](const ::testing::TestParamInfo<Layout>& tested) {
                           return layoutName(tested.param);
                         });

}  // namespace
}  // namespace slicecap::fit::detail
