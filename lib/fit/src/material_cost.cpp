// Residuals 255 g(f cos_i / M) - target and their derivatives, chained by hand through g and the
// linear colours; Jets only for the lobe shapes.
#include "material_cost.hpp"

#include <ceres/jet.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace slicecap::fit::detail {
namespace {

using Jet3 = ceres::Jet<double, 3>;
using Jet1 = ceres::Jet<double, 1>;

}  // namespace

MaterialCost::MaterialCost(const FitData& data, bool withSheen, bool withCoat, SheenForm sheenForm)
    : data_(data), withSheen_(withSheen), withCoat_(withCoat), sheenForm_(sheenForm) {
  set_num_residuals(data.residualCount());
  std::vector<int32_t>& sizes = *mutable_parameter_block_sizes();
  sizes.assign({kGgxParameters});
  if (withSheen) sizes.push_back(kSheenParameters);
  if (withCoat) sizes.push_back(kCoatParameters);
}

bool MaterialCost::Evaluate(double const* const* parameters, double* residuals,
                            double** jacobians) const {
  const int sheenBlock = withSheen_ ? 1 : -1;
  const int coatBlock = withCoat_ ? (withSheen_ ? 2 : 1) : -1;
  const double* ggx = parameters[0];
  const double* sheen = withSheen_ ? parameters[sheenBlock] : nullptr;
  const double* coat = withCoat_ ? parameters[coatBlock] : nullptr;
  double* ggxJacobian = jacobians ? jacobians[0] : nullptr;
  double* sheenJacobian = (jacobians && withSheen_) ? jacobians[sheenBlock] : nullptr;
  double* coatJacobian = (jacobians && withCoat_) ? jacobians[coatBlock] : nullptr;
  const bool shapeDerivatives =
      ggxJacobian != nullptr || sheenJacobian != nullptr || coatJacobian != nullptr;

  const Jet3 alphaT = exp(Jet3(ggx[6], 0)), alphaB = exp(Jet3(ggx[7], 1));
  const Jet3 tangent(ggx[8], 2);
  const Jet3 cosT = cos(tangent), sinT = sin(tangent);
  const double alphaTValue = std::exp(ggx[6]), alphaBValue = std::exp(ggx[7]);
  const double cosTValue = std::cos(ggx[8]), sinTValue = std::sin(ggx[8]);
  const Jet1 sheenRoughness = sheen ? exp(Jet1(sheen[3], 0)) : Jet1(1.0);
  const double sheenRoughnessValue = sheenRoughness.a;
  const Jet1 coatAlpha = coat ? exp(Jet1(coat[1], 0)) : Jet1(1.0);
  const double coatWeight = coat ? coat[0] : 0.0;
  // KHR_materials_sheen's layering: the base is scaled by 1 - s E, s the largest sheen channel
  // (its derivative goes to that channel alone).
  const bool khr = sheen != nullptr && sheenForm_ == SheenForm::Khr;
  int brightestSheen = 0;
  if (khr)
    for (int c = 1; c < 3; ++c)
      if (sheen[c] > sheen[brightestSheen]) brightestSheen = c;
  const double sheenMax = khr ? sheen[brightestSheen] : 0.0;

  for (std::size_t i = 0; i < data_.pairs.size(); ++i) {
    const PairGeometry& g = data_.pairs[i];
    Jet3 specular;
    Jet1 sheenShape, sheenAlbedo(0.0), coatShape;
    if (shapeDerivatives) {
      specular = ggxSpecular(g, alphaT, alphaB, cosT, sinT);
      if (sheen) sheenShape = khr ? khrSheenLobe(g, sheenRoughness) : sheenLobe(g, sheenRoughness);
      if (khr) sheenAlbedo = khrSheenAlbedoMax(g, sheenRoughness);
      if (coat) coatShape = ggxSpecular(g, coatAlpha, coatAlpha, Jet1(1.0), Jet1(0.0));
    } else {
      specular = Jet3(ggxSpecular(g, alphaTValue, alphaBValue, cosTValue, sinTValue));
      if (sheen)
        sheenShape = Jet1(khr ? khrSheenLobe(g, sheenRoughnessValue)
                              : sheenLobe(g, sheenRoughnessValue));
      if (khr) sheenAlbedo = Jet1(khrSheenAlbedoMax(g, sheenRoughnessValue));
      if (coat) coatShape = Jet1(ggxSpecular(g, coatAlpha.a, coatAlpha.a, 1.0, 0.0));
    }
    const double scaling = 1.0 - sheenMax * sheenAlbedo.a;  // 1 unless khr
    // The coat takes w Fc of the light and leaves the base the rest (glTF's fresnel_coat mix).
    const double coatShare = coatWeight * g.coatFresnel;
    const double baseShare = 1.0 - coatShare;
    for (int c = 0; c < 3; ++c) {
      const double fresnel = ggx[3 + c] + (ggx[9] - ggx[3 + c]) * g.fresnelWeight;
      const double under = ggx[c] / std::numbers::pi + fresnel * specular.a;  // under the sheen
      double base = under * scaling;
      if (sheen) base += sheen[c] * sheenShape.a;
      const double value = coat ? base * baseShare + coatShare * coatShape.a : base;
      const double x = value * data_.scale[i];
      const std::size_t row = 3 * i + static_cast<std::size_t>(c);
      const double curve = srgbCurve(x);
      residuals[row] = 255.0 * curve - data_.target[i][static_cast<std::size_t>(c)];
      if (!shapeDerivatives) continue;
      const double k = 255.0 * srgbSlope(x, curve) * data_.scale[i];  // d residual / d value
      const double kBase = coat ? k * baseShare : k;                    // d residual / d base
      const double kUnder = kBase * scaling;                            // d residual / d under
      if (ggxJacobian) {
        double* r = ggxJacobian + row * kGgxParameters;
        for (int p = 0; p < kGgxParameters; ++p) r[p] = 0.0;
        r[c] = kUnder / std::numbers::pi;
        r[3 + c] = kUnder * (1.0 - g.fresnelWeight) * specular.a;
        for (int p = 0; p < 3; ++p) r[6 + p] = kUnder * fresnel * specular.v[p];
        r[9] = kUnder * g.fresnelWeight * specular.a;
      }
      if (sheenJacobian) {
        double* r = sheenJacobian + row * kSheenParameters;
        for (int p = 0; p < kSheenParameters; ++p) r[p] = 0.0;
        r[c] = kBase * sheenShape.a;
        r[3] = kBase * (sheen[c] * sheenShape.v[0] - sheenMax * sheenAlbedo.v[0] * under);
        if (khr) r[brightestSheen] -= kBase * sheenAlbedo.a * under;
      }
      if (coatJacobian) {
        double* r = coatJacobian + row * kCoatParameters;
        r[0] = k * g.coatFresnel * (coatShape.a - base);
        r[1] = k * coatShare * coatShape.v[0];
      }
    }
  }
  return std::isfinite(residuals[0]);
}

}  // namespace slicecap::fit::detail
